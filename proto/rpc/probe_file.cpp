#include "rpc/probe_file.h"

#include <cmath>
#include <cstring>
#include <nlohmann/json.hpp>

namespace ddgi {
namespace {

void append_floats(std::string& out, const std::vector<float>& values) {
  static_assert(sizeof(float) == 4);
  const size_t at = out.size();
  out.resize(at + values.size() * 4);
  std::memcpy(out.data() + at, values.data(), values.size() * 4);  // little-endian hosts
}

Result<std::vector<float>> take_floats(const std::string& bytes, size_t* at, size_t count,
                                       const char* what) {
  if (count > (bytes.size() - *at) / 4) {
    return invalid_argument(std::string("probe file: ") + what + " runs past the end");
  }
  std::vector<float> values(count);
  std::memcpy(values.data(), bytes.data() + *at, count * 4);
  *at += count * 4;
  return values;
}

}  // namespace

std::string encode_probe_file(const ProbeFile& file) {
  const ProbeField& f = file.field;
  const bool sh = f.basis == kProbeBasisSh;
  nlohmann::json header = {{"basis", sh ? "sh" : "octahedral"},
                           {"counts", {f.counts[0], f.counts[1], f.counts[2]}},
                           {"origin", {f.origin.x, f.origin.y, f.origin.z}},
                           {"spacing", {f.spacing.x, f.spacing.y, f.spacing.z}},
                           {"self_shadow_bias", f.self_shadow_bias},
                           {"weight_crush_threshold", f.weight_crush_threshold},
                           {"field_updates", file.field_updates},
                           {"session_id", file.session_id}};
  if (sh) {
    header["sh_band_scales"] = {f.sh_band_scales[0], f.sh_band_scales[1], f.sh_band_scales[2]};
  } else {
    header.update({{"irradiance_texels", f.irradiance_texels},
                   {"distance_texels", f.distance_texels},
                   {"border_texels", f.border_texels},
                   {"tiles_per_row", f.tiles_per_row},
                   {"irradiance_gamma", f.irradiance_gamma},
                   {"irradiance_size", {f.irradiance_width, f.irradiance_height}},
                   {"distance_size", {f.distance_width, f.distance_height}}});
  }
  std::string text = header.dump();
  text.append((4 - (12 + text.size()) % 4) % 4, ' ');  // the floats start 4-byte aligned
  std::string out(kProbeFileMagic, 8);
  const uint32_t length = uint32_t(text.size());
  for (int byte = 0; byte < 4; ++byte) out.push_back(char((length >> (8 * byte)) & 0xff));
  out += text;
  if (sh) {
    append_floats(out, f.sh);
  } else {
    append_floats(out, f.irradiance);
    append_floats(out, f.distance);
  }
  append_floats(out, f.probe_states);
  return out;
}

Result<ProbeFile> decode_probe_file(const std::string& bytes) {
  if (bytes.size() < 12 || bytes.compare(0, 8, kProbeFileMagic) != 0) {
    return invalid_argument("not a probe file (it does not start with DDGIPRB1)");
  }
  uint32_t length = 0;
  for (int byte = 0; byte < 4; ++byte) length |= uint32_t(uint8_t(bytes[8 + byte])) << (8 * byte);
  if (length > bytes.size() - 12) return invalid_argument("probe file: header past the end");
  ProbeFile file;
  ProbeField& f = file.field;
  try {
    const nlohmann::json h = nlohmann::json::parse(bytes.substr(12, length));
    for (int axis = 0; axis < 3; ++axis) {
      f.counts[axis] = h.at("counts").at(axis).get<int>();
    }
    f.origin = {h.at("origin").at(0), h.at("origin").at(1), h.at("origin").at(2)};
    f.spacing = {h.at("spacing").at(0), h.at("spacing").at(1), h.at("spacing").at(2)};
    const std::string basis = h.value("basis", "octahedral");
    if (basis != "octahedral" && basis != "sh") {
      return invalid_argument("probe file: basis must be octahedral or sh (got '" + basis + "')");
    }
    f.self_shadow_bias = h.at("self_shadow_bias");
    f.weight_crush_threshold = h.at("weight_crush_threshold");
    if (basis == "sh") {
      f.basis = kProbeBasisSh;
      for (int band = 0; band < 3; ++band) {
        f.sh_band_scales[band] = h.at("sh_band_scales").at(band);
      }
    } else {
      f.irradiance_texels = h.at("irradiance_texels");
      f.distance_texels = h.at("distance_texels");
      f.border_texels = h.at("border_texels");
      f.tiles_per_row = h.at("tiles_per_row");
      f.irradiance_gamma = h.at("irradiance_gamma");
      f.irradiance_width = h.at("irradiance_size").at(0);
      f.irradiance_height = h.at("irradiance_size").at(1);
      f.distance_width = h.at("distance_size").at(0);
      f.distance_height = h.at("distance_size").at(1);
    }
    file.field_updates = h.at("field_updates");
    file.session_id = h.at("session_id");
  } catch (const nlohmann::json::exception& error) {
    return invalid_argument(std::string("probe file header: ") + error.what());
  }
  if (f.counts[0] <= 0 || f.counts[1] <= 0 || f.counts[2] <= 0 ||
      int64_t(f.counts[0]) * f.counts[1] * f.counts[2] > (1 << 24)) {
    return invalid_argument("probe file: counts must be positive, at most 2^24 probes");
  }
  // Limits far above any field the server makes, so that no size computation can overflow.
  for (const uint32_t side : {f.irradiance_width, f.irradiance_height, f.distance_width,
                              f.distance_height, f.tiles_per_row}) {
    if (side > (1u << 16)) return invalid_argument("probe file: an atlas side over 65536");
  }
  if (f.irradiance_texels > 64 || f.distance_texels > 64 || f.border_texels > 8) {
    return invalid_argument("probe file: texels per probe over 64 or a border over 8");
  }
  for (const float value :
       {f.origin.x, f.origin.y, f.origin.z, f.spacing.x, f.spacing.y, f.spacing.z,
        f.irradiance_gamma, f.self_shadow_bias, f.weight_crush_threshold, f.sh_band_scales[0],
        f.sh_band_scales[1], f.sh_band_scales[2]}) {
    if (!std::isfinite(value)) return invalid_argument("probe file: a non-finite parameter");
  }
  size_t at = 12 + length;
  const size_t probes = size_t(f.counts[0]) * size_t(f.counts[1]) * size_t(f.counts[2]);
  if (f.basis == kProbeBasisSh) {
    DDGI_ASSIGN_OR_RETURN(f.sh, take_floats(bytes, &at, probes * 27, "the SH coefficients"));
  } else {
    DDGI_ASSIGN_OR_RETURN(
        f.irradiance, take_floats(bytes, &at, size_t(f.irradiance_width) * f.irradiance_height * 4,
                                  "the irradiance atlas"));
    DDGI_ASSIGN_OR_RETURN(f.distance,
                          take_floats(bytes, &at, size_t(f.distance_width) * f.distance_height * 2,
                                      "the distance atlas"));
  }
  DDGI_ASSIGN_OR_RETURN(f.probe_states, take_floats(bytes, &at, probes * 4, "the probe states"));
  if (at != bytes.size()) return invalid_argument("probe file: bytes after the probe states");
  if (const std::string problem = probe_field_problem(f); !problem.empty()) {
    return invalid_argument("probe file: " + problem);
  }
  return file;
}

}  // namespace ddgi
