// probes.bin (rpc/probe_file.h) and the evaluator on a field made by hand: a file survives
// the round trip bit for bit; a damaged or lying file is refused naming what is wrong; and the
// evaluator returns what a field of uniform light must give: a grid whose every texel encodes
// radiance L gives L everywhere (gamma decoded, any point, any normal), and switching every
// probe off gives black.
#include <gtest/gtest.h>

#include <cmath>

#include "rpc/probe_file.h"
#include "rpc/probe_stream.h"

namespace ddgi {
namespace {

// A 2x3x2 grid with 4x4 irradiance and 6x6 distance texels, every texel the same: encoded
// irradiance value^(1/gamma), distances far beyond the grid (nothing occludes).
ProbeFile uniform_field(float radiance, float gamma) {
  ProbeFile file;
  ProbeField& f = file.field;
  f.counts[0] = 2;
  f.counts[1] = 3;
  f.counts[2] = 2;
  f.origin = {-1.0f, 0.0f, -1.0f};
  f.spacing = {2.0f, 1.0f, 2.0f};
  f.irradiance_texels = 4;
  f.distance_texels = 6;
  f.border_texels = 1;
  f.tiles_per_row = 4;
  f.irradiance_gamma = gamma;
  const uint32_t rows = 3;  // 12 probes, 4 per row
  f.irradiance_width = 4 * 6;
  f.irradiance_height = rows * 6;
  f.distance_width = 4 * 8;
  f.distance_height = rows * 8;
  f.irradiance.assign(size_t(f.irradiance_width) * f.irradiance_height * 4,
                      std::pow(radiance, 1.0f / gamma));
  f.distance.resize(size_t(f.distance_width) * f.distance_height * 2);
  for (size_t i = 0; i < f.distance.size(); i += 2) {
    f.distance[i] = 100.0f;
    f.distance[i + 1] = 100.0f * 100.0f;
  }
  f.probe_states.assign(12 * 4, 0.0f);
  file.field_updates = 42;
  file.session_id = "s0123456789abcdef";
  return file;
}

TEST(ProbeFile, RoundTripsBitForBit) {
  const ProbeFile file = uniform_field(0.25f, 5.0f);
  ASSERT_STREQ(probe_field_problem(file.field), "");
  const std::string bytes = encode_probe_file(file);
  EXPECT_EQ((bytes.size() - 12) % 4, 0u);
  Result<ProbeFile> back = decode_probe_file(bytes);
  ASSERT_TRUE(back.ok()) << back.error().message;
  EXPECT_EQ(back->field.irradiance, file.field.irradiance);
  EXPECT_EQ(back->field.distance, file.field.distance);
  EXPECT_EQ(back->field.probe_states, file.field.probe_states);
  EXPECT_EQ(back->field.tiles_per_row, 4u);
  EXPECT_EQ(back->field.counts[1], 3);
  EXPECT_EQ(back->field_updates, 42u);
  EXPECT_EQ(back->session_id, file.session_id);
  EXPECT_EQ(encode_probe_file(*back), bytes);
}

TEST(ProbeFile, DamagedFilesAreRefusedNamingWhy) {
  const std::string good = encode_probe_file(uniform_field(0.25f, 5.0f));
  auto refused = [](const std::string& bytes) {
    Result<ProbeFile> file = decode_probe_file(bytes);
    return file.ok() ? std::string("accepted") : file.error().message;
  };
  EXPECT_NE(refused("PNG....").find("not a probe file"), std::string::npos);
  EXPECT_NE(refused(good.substr(0, good.size() - 4)).find("runs past the end"), std::string::npos);
  EXPECT_NE(refused(good + "xxxx").find("bytes after"), std::string::npos);
  std::string lying = good;
  lying.replace(lying.find("\"counts\":[2,3,2]"), 16, "\"counts\":[2,9,2]");
  EXPECT_NE(refused(lying), "accepted");
  std::string huge = good;
  // The same length, so that the header keeps its size.
  huge.replace(huge.find("\"irradiance_size\":[24,18]"), 25, "\"irradiance_size\":[1e6,1]");
  EXPECT_NE(refused(huge).find("over 65536"), std::string::npos) << refused(huge);
  std::string broken = good;
  broken[13] = '!';
  EXPECT_NE(refused(broken).find("header"), std::string::npos);
}

TEST(ProbeField, UniformLightGivesItsRadianceEverywhere) {
  const float radiance = 0.37f;
  const ProbeFile file = uniform_field(radiance, 5.0f);
  const ProbeVec3 points[] = {{0.0f, 1.0f, 0.0f}, {-0.9f, 0.1f, 0.7f}, {3.0f, -2.0f, 5.0f}};
  const ProbeVec3 normals[] = {{0.0f, 1.0f, 0.0f}, {0.6f, 0.0f, -0.8f}, {0.0f, 0.0f, -1.0f}};
  for (const ProbeVec3& p : points) {
    for (const ProbeVec3& n : normals) {
      const ProbeVec3 e = probe_field_irradiance(file.field, p, n, n);
      EXPECT_NEAR(e.x, radiance, 1e-5f);
      EXPECT_NEAR(e.z, radiance, 1e-5f);
    }
  }
  // The control: every probe off gives black, one probe on gives the light back.
  ProbeFile off = file;
  for (size_t i = 3; i < off.field.probe_states.size(); i += 4) off.field.probe_states[i] = 3.0f;
  EXPECT_EQ(probe_field_irradiance(off.field, points[0], normals[0], normals[0]).y, 0.0f);
  off.field.probe_states[2 * 4 + 3] = 0.0f;  // probe (0, 1, 0), in the point's cage
  EXPECT_NEAR(probe_field_irradiance(off.field, points[0], normals[0], normals[0]).y, radiance,
              1e-5f);
}

// An SH field of 2x2x2 probes that all see radiance L from above (y > 0) and nothing below:
// the L2 projection of that light is exact for irradiance (its band-2 part is zero), so M must
// be L facing up, L / 2 facing sideways, 0 facing down, and (1 + ny) / 2 L between.
ProbeFile sky_sh_field(float radiance) {
  ProbeFile file;
  ProbeField& f = file.field;
  f.basis = kProbeBasisSh;
  f.counts[0] = f.counts[1] = f.counts[2] = 2;
  f.spacing = {1.0f, 1.0f, 1.0f};
  f.probe_states.assign(8 * 4, 0.0f);
  f.sh.assign(8 * 27, 0.0f);
  const float pi = 3.14159265f;
  for (size_t p = 0; p < 8; ++p) {
    for (int c = 0; c < 3; ++c) {
      f.sh[p * 27 + 0 * 3 + c] = radiance * 2.0f * pi * 0.282094792f;  // L_00
      f.sh[p * 27 + 1 * 3 + c] = radiance * pi * 0.488602512f;         // y's band-1 function
    }
  }
  file.session_id = "s0123456789abcdef";
  return file;
}

TEST(ProbeField, ShSkyGivesTheAnalyticIrradiance) {
  const float radiance = 0.8f;
  ProbeFile file = sky_sh_field(radiance);
  ASSERT_STREQ(probe_field_problem(file.field), "");
  Result<ProbeFile> back = decode_probe_file(encode_probe_file(file));
  ASSERT_TRUE(back.ok()) << back.error().message;
  EXPECT_EQ(back->field.sh, file.field.sh);
  EXPECT_EQ(back->field.basis, kProbeBasisSh);
  for (const float ny : {1.0f, 0.6f, 0.0f, -0.5f, -1.0f}) {
    const ProbeVec3 n{std::sqrt(1.0f - ny * ny), ny, 0.0f};
    const ProbeVec3 e = probe_field_irradiance(back->field, {0.5f, 0.3f, 0.6f}, n, n);
    EXPECT_NEAR(e.y, radiance * (1.0f + ny) * 0.5f, 1e-5f) << "n.y " << ny;
  }
  // The control: band 1 at the factor of band 2 no longer gives the sky.
  back->field.sh_band_scales[1] = 0.25f;
  const ProbeVec3 up{0.0f, 1.0f, 0.0f};
  EXPECT_GT(std::abs(probe_field_irradiance(back->field, {0.5f, 0.3f, 0.6f}, up, up).y - radiance),
            0.1f);
  // A file whose coefficients are short is refused.
  file.field.sh.pop_back();
  EXPECT_STRNE(probe_field_problem(file.field), "");
}

// The stream's fp16 (rpc/probe_stream.h) against values IEEE binary16 defines exactly.
TEST(ProbeStream, HalfFloatsRoundToNearestEven) {
  EXPECT_EQ(float_to_half(1.0f), 0x3c00);
  EXPECT_EQ(float_to_half(-2.0f), 0xc000);
  EXPECT_EQ(float_to_half(65504.0f), 0x7bff);
  EXPECT_EQ(float_to_half(1e9f), 0x7bff) << "beyond the largest half: clamped";
  EXPECT_EQ(float_to_half(5.9604645e-8f), 0x0001) << "the smallest subnormal";
  EXPECT_EQ(float_to_half(1.0f + 1.0f / 2048.0f), 0x3c00) << "a tie rounds to even (down)";
  EXPECT_EQ(float_to_half(1.0f + 3.0f / 2048.0f), 0x3c02) << "a tie rounds to even (up)";
  EXPECT_EQ(float_to_half(std::nanf("")), 0);
  for (const float v : {0.0f, 0.1f, 0.37f, 3.14159f, 1000.5f, 6.1e-5f, -7.25f}) {
    const float back = half_to_float(float_to_half(v));
    EXPECT_LE(std::abs(back - v), std::abs(v) / 2048.0f + 3e-8f) << v;
    EXPECT_EQ(float_to_half(back), float_to_half(v)) << "a half survives the round trip";
  }
}

}  // namespace
}  // namespace ddgi
