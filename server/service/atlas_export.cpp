#include "service/atlas_export.h"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfIO.h>
#include <ImfOutputFile.h>
#include <ImfStringAttribute.h>

#include <algorithm>
#include <cstring>
#include <exception>
#include <string>

#include "gi/probe_state.h"
#include "shared/field_data.h"
#include "shared/shadow_field_data.h"

namespace ddgi::service {
namespace {

// OpenEXR writes through a stream; this one keeps the file in memory.
class MemoryStream : public Imf::OStream {
 public:
  MemoryStream() : Imf::OStream("atlas") {}
  void write(const char c[], int n) override {
    if (position_ + size_t(n) > bytes_.size()) bytes_.resize(position_ + size_t(n));
    std::memcpy(bytes_.data() + position_, c, size_t(n));
    position_ += size_t(n);
  }
  uint64_t tellp() override { return position_; }
  void seekp(uint64_t position) override { position_ = position; }
  std::vector<uint8_t> take() { return std::move(bytes_); }

 private:
  std::vector<uint8_t> bytes_;
  size_t position_ = 0;
};

std::string vec_text(const v1::Vec3& v) {
  return std::to_string(v.x()) + " " + std::to_string(v.y()) + " " + std::to_string(v.z());
}

// The dump's metadata as EXR string attributes.
void add_attributes(Imf::Header& header, const v1::AtlasMetadata& m) {
  auto add = [&](const char* name, const std::string& value) {
    header.insert(std::string("ddgi.") + name, Imf::StringAttribute(value));
  };
  add("kind", v1::AtlasKind_Name(m.kind()));
  std::string channels;
  for (const std::string& c : m.channels()) channels += (channels.empty() ? "" : " ") + c;
  add("channels", channels);
  add("probe_counts", std::to_string(m.probe_counts_x()) + " " +
                          std::to_string(m.probe_counts_y()) + " " +
                          std::to_string(m.probe_counts_z()));
  add("grid_origin", vec_text(m.grid_origin()));
  add("probe_spacing", vec_text(m.probe_spacing()));
  add("texels_per_probe", std::to_string(m.texels_per_probe()));
  add("border_texels", std::to_string(m.border_texels()));
  add("tiles_per_row", std::to_string(m.tiles_per_row()));
  add("encoding_gamma", std::to_string(m.encoding_gamma()));
  add("field_updates", std::to_string(m.field_updates()));
  add("description", m.description());
}

}  // namespace

namespace {

void set_vec(v1::Vec3* out, const glm::vec3& v) {
  out->set_x(v.x);
  out->set_y(v.y);
  out->set_z(v.z);
}

void set_grid(v1::AtlasMetadata& m, const glm::vec3& origin, const glm::vec3& spacing,
              const glm::ivec3& counts) {
  m.set_probe_counts_x(counts.x);
  m.set_probe_counts_y(counts.y);
  m.set_probe_counts_z(counts.z);
  set_vec(m.mutable_grid_origin(), origin);
  set_vec(m.mutable_probe_spacing(), spacing);
}

v1::AtlasMetadata field_metadata(const IrradianceField& field, const FieldVolume& volume,
                                 v1::AtlasKind kind, v1::AtlasFormat format,
                                 const AtlasImage& image) {
  const IrradianceFieldParams& p = field.params();
  v1::AtlasMetadata m;
  m.set_kind(kind);
  m.set_format(format);
  m.set_width(image.width);
  m.set_height(image.height);
  set_grid(m, volume.origin, volume.spacing, volume.counts);
  m.set_border_texels(gpu::kAtlasBorder);
  m.set_tiles_per_row(atlas_layout(p).tiles_per_row);
  m.set_field_updates(field.updates());
  if (kind == v1::ATLAS_KIND_IRRADIANCE) {
    for (const char* c : {"R", "G", "B", "A"}) m.add_channels(c);
    m.set_texels_per_probe(p.irradiance_texels);
    m.set_encoding_gamma(p.irradiance_gamma);
    m.set_description(
        "octahedral irradiance per probe, tiles of (texels+2*border)^2 in probe order "
        "(x fastest, then y, then z), row-major tiles; RGB = (E/pi)^(1/encoding_gamma)");
  } else {
    for (const char* c : {"mean", "mean2"}) m.add_channels(c);
    m.set_texels_per_probe(p.distance_texels);
    m.set_encoding_gamma(1.0f);
    m.set_description(
        "octahedral distance moments per probe, same tiling as irradiance; channel 0 = mean hit "
        "distance, channel 1 = mean squared distance (world units)");
  }
  return m;
}

v1::AtlasMetadata shadow_metadata(const ShadowField& shadow, v1::AtlasKind kind,
                                  v1::AtlasFormat format, const AtlasImage& image) {
  const ShadowFieldParams& p = shadow.params();
  v1::AtlasMetadata m;
  m.set_kind(kind);
  m.set_format(format);
  m.set_width(image.width);
  m.set_height(image.height);
  set_grid(m, p.origin, p.spacing, p.counts);
  m.set_border_texels(gpu::kShadowAtlasBorder);
  m.set_tiles_per_row(shadow.atlas_layout().tiles_per_row);
  m.set_texels_per_probe(p.texels);
  m.set_encoding_gamma(1.0f);
  m.set_field_updates(shadow.updates());
  if (kind == v1::ATLAS_KIND_SHADOW) {
    for (const char* c : {"light0", "light1", "light2", "light3"}) m.add_channels(c);
    m.set_description(
        "octahedral light visibility per probe in [0,1], tiles of (texels+2*border)^2 in probe "
        "order; " +
        std::to_string(shadow.atlas_layout().light_groups) + " band(s) of " +
        std::to_string(shadow.atlas_layout().tile_rows) +
        " tile rows stacked vertically: band k holds lights 4k..4k+3 in its channels; " +
        std::to_string(shadow.kept_lights()) + " light(s) kept");
  } else {
    for (const char* c : {"mean", "mean2", "ao", "weight"}) m.add_channels(c);
    m.set_description(
        "octahedral moments per probe, same tiling as the visibility's first band: mean hit "
        "distance, mean squared distance (world units), ambient occlusion, history weight");
  }
  return m;
}

// One row per probe: its nine SH coefficients, RGB.
std::pair<v1::AtlasMetadata, AtlasImage> sh_dump(const IrradianceField& field,
                                                 const FieldVolume& volume,
                                                 const std::vector<gpu::ShProbe>& probes,
                                                 v1::AtlasFormat format) {
  const IrradianceFieldParams& p = field.params();
  AtlasImage image;
  image.width = 9;
  image.height = static_cast<uint32_t>(probes.size());
  image.channels = 3;
  image.texels = sh_coefficient_values(probes);
  v1::AtlasMetadata m;
  m.set_kind(v1::ATLAS_KIND_SH);
  m.set_format(format);
  m.set_width(image.width);
  m.set_height(image.height);
  set_grid(m, volume.origin, volume.spacing, volume.counts);
  m.set_texels_per_probe(9);
  m.set_tiles_per_row(1);
  m.set_encoding_gamma(1.0f);
  m.set_field_updates(field.updates());
  for (const char* c : {"R", "G", "B"}) m.add_channels(c);
  for (const float scale : sh_band_scales(p)) m.add_sh_band_scales(scale);
  m.set_description(
      "one row per probe (x fastest, then y, then z), nine texels: the L2 SH coefficients of the "
      "radiance the probe sees (order of shaders/common/sh.glsl: l=0; l=1 m=-1,0,1; l=2 "
      "m=-2..2), RGB; M = E/pi = sum_l sh_band_scales[l] sum_m L_lm Y_lm(n)");
  return {std::move(m), std::move(image)};
}

// One texel per probe: relocation offset and state.
std::pair<v1::AtlasMetadata, AtlasImage> probe_state_dump(
    const IrradianceField& field, const FieldVolume& volume,
    const std::vector<gpu::ProbeState>& states, v1::AtlasFormat format) {
  AtlasImage image;
  image.width = static_cast<uint32_t>(volume.counts.x);
  image.height = static_cast<uint32_t>(volume.counts.y * volume.counts.z);
  image.channels = 4;
  image.texels = probe_state_values(states);
  v1::AtlasMetadata m;
  m.set_kind(v1::ATLAS_KIND_PROBE_STATES);
  m.set_format(format);
  m.set_width(image.width);
  m.set_height(image.height);
  set_grid(m, volume.origin, volume.spacing, volume.counts);
  m.set_texels_per_probe(1);
  m.set_tiles_per_row(image.width);
  m.set_encoding_gamma(1.0f);
  m.set_field_updates(field.updates());
  for (const char* c : {"offset_x", "offset_y", "offset_z", "state"}) m.add_channels(c);
  m.set_description(
      "one texel per probe, x fastest then y then z (row = y + z * probes_y): relocation offset "
      "from the grid position (world units) and state (0 vigilant, 1 awake, 2 sleeping, 3 off)");
  return {std::move(m), std::move(image)};
}

// A float atlas (RGBA32F or RG32F, GENERAL layout) on the CPU.
Result<AtlasImage> read_float_image(vk::Context& context, const vk::Image& image) {
  AtlasImage atlas;
  atlas.width = image.width();
  atlas.height = image.height();
  atlas.channels = vk::float_channels(image.format());
  if (atlas.channels == 0) {
    return internal_error("the atlas image is not in a float format the dump knows");
  }
  atlas.texels.resize(size_t(atlas.width) * atlas.height * atlas.channels);
  DDGI_TRY(
      vk::download_image(context, image, atlas.texels.data(), atlas.texels.size() * sizeof(float)));
  return atlas;
}

// The probes of `volume` from a list of every volume's (grid order, volume after volume).
template <typename T>
std::vector<T> volume_probes(const std::vector<T>& all, const FieldVolume& volume) {
  const auto first = all.begin() + volume.first_probe;
  const size_t count = size_t(volume.counts.x) * volume.counts.y * volume.counts.z;
  return std::vector<T>(first, first + std::ptrdiff_t(count));
}

// The tiles of `volume` from an atlas of every volume's (grid order, `tiles_per_row` tiles of
// (texels + 2 borders)^2 per row), laid out as the atlas of that volume alone: the same tiles
// per row, as many rows as its probes fill. A field of one volume is returned as it is.
AtlasImage volume_tiles(const AtlasImage& all, uint32_t tiles_per_row, uint32_t texels,
                        const FieldVolume& volume) {
  const uint32_t count = uint32_t(volume.counts.x * volume.counts.y * volume.counts.z);
  const uint32_t side = texels + 2 * gpu::kAtlasBorder;
  const uint32_t rows = (count + tiles_per_row - 1) / tiles_per_row;
  if (volume.first_probe == 0 && rows * side == all.height) return all;
  AtlasImage image;
  image.width = all.width;
  image.height = rows * side;
  image.channels = all.channels;
  image.texels.assign(size_t(image.width) * image.height * image.channels, 0.0f);
  auto tile_start = [&](uint32_t tile) {
    return (size_t(tile / tiles_per_row) * side * all.width + size_t(tile % tiles_per_row) * side) *
           all.channels;
  };
  const size_t row_values = size_t(side) * all.channels;
  for (uint32_t g = 0; g < count; ++g) {
    for (uint32_t y = 0; y < side; ++y) {
      const size_t row = size_t(y) * all.width * all.channels;
      std::copy_n(all.texels.begin() + std::ptrdiff_t(tile_start(volume.first_probe + g) + row),
                  row_values, image.texels.begin() + std::ptrdiff_t(tile_start(g) + row));
    }
  }
  return image;
}

}  // namespace

Result<std::pair<v1::AtlasMetadata, AtlasImage>> read_atlas(vk::Context& context,
                                                            IrradianceField* field,
                                                            ShadowField* shadow,
                                                            const AtlasRequest& request) {
  switch (request.kind) {
    case v1::ATLAS_KIND_IRRADIANCE:
    case v1::ATLAS_KIND_DISTANCE: {
      if (field == nullptr) return failed_precondition("this session has no irradiance field");
      DDGI_ASSIGN_OR_RETURN(const FieldVolume volume, field->volume(request.volume));
      DDGI_ASSIGN_OR_RETURN(const AtlasImage all, request.kind == v1::ATLAS_KIND_IRRADIANCE
                                                      ? field->read_irradiance_atlas()
                                                      : field->read_distance_atlas());
      const IrradianceFieldParams& p = field->params();
      const uint32_t texels =
          request.kind == v1::ATLAS_KIND_IRRADIANCE ? p.irradiance_texels : p.distance_texels;
      AtlasImage image = volume_tiles(all, atlas_layout(p).tiles_per_row, texels, volume);
      v1::AtlasMetadata metadata =
          field_metadata(*field, volume, request.kind, request.format, image);
      return std::make_pair(std::move(metadata), std::move(image));
    }
    case v1::ATLAS_KIND_SHADOW:
    case v1::ATLAS_KIND_SHADOW_MOMENTS: {
      if (shadow == nullptr) {
        return failed_precondition(
            "this session has no shadow field (create it with direct_mode SHADOW_FIELD or "
            "AMBIENT_OCCLUSION)");
      }
      if (request.volume != 0) {
        return invalid_argument("volume " + std::to_string(request.volume) +
                                ": the shadow field has one volume, 0");
      }
      DDGI_ASSIGN_OR_RETURN(AtlasImage image,
                            read_float_image(context, request.kind == v1::ATLAS_KIND_SHADOW
                                                          ? shadow->visibility_atlas()
                                                          : shadow->moments_atlas()));
      v1::AtlasMetadata metadata = shadow_metadata(*shadow, request.kind, request.format, image);
      return std::make_pair(std::move(metadata), std::move(image));
    }
    case v1::ATLAS_KIND_SH: {
      if (field == nullptr) return failed_precondition("this session has no irradiance field");
      DDGI_ASSIGN_OR_RETURN(const FieldVolume volume, field->volume(request.volume));
      DDGI_ASSIGN_OR_RETURN(const std::vector<gpu::ShProbe> probes, field->read_sh_probes());
      return sh_dump(*field, volume, volume_probes(probes, volume), request.format);
    }
    case v1::ATLAS_KIND_PROBE_STATES: {
      if (field == nullptr) return failed_precondition("this session has no irradiance field");
      DDGI_ASSIGN_OR_RETURN(const FieldVolume volume, field->volume(request.volume));
      DDGI_ASSIGN_OR_RETURN(const std::vector<gpu::ProbeState> states, field->read_probe_states());
      return probe_state_dump(*field, volume, volume_probes(states, volume), request.format);
    }
    default:
      return invalid_argument("atlas kind " + std::to_string(int(request.kind)) + " is not dumped");
  }
}

Result<std::vector<uint8_t>> encode_atlas(const AtlasImage& image, v1::AtlasMetadata& metadata) {
  const size_t values = size_t(image.width) * image.height * image.channels;
  if (image.texels.size() != values || image.channels == 0 || image.channels > 4) {
    return internal_error("atlas image has " + std::to_string(image.texels.size()) +
                          " values, expected " + std::to_string(values));
  }
  std::vector<uint8_t> bytes;
  if (metadata.format() == v1::ATLAS_FORMAT_RAW_F32) {
    // The host is little-endian (x86-64, aarch64), which is what the format promises.
    bytes.resize(values * sizeof(float));
    std::memcpy(bytes.data(), image.texels.data(), bytes.size());
  } else {
    try {
      // EXR channel names stay R, G, B, A so every viewer opens the file; ddgi.channels says
      // what they hold.
      static const char* const kNames[] = {"R", "G", "B", "A"};
      Imf::Header header(static_cast<int>(image.width), static_cast<int>(image.height));
      header.compression() = Imf::ZIP_COMPRESSION;
      for (uint32_t c = 0; c < image.channels; ++c) {
        header.channels().insert(kNames[c], Imf::Channel(Imf::FLOAT));
      }
      add_attributes(header, metadata);
      MemoryStream stream;
      {
        // OutputFile writes the line-offset table when it is destroyed: end its scope first.
        Imf::OutputFile file(stream, header);
        Imf::FrameBuffer frame_buffer;
        const size_t x_stride = sizeof(float) * image.channels;
        for (uint32_t c = 0; c < image.channels; ++c) {
          frame_buffer.insert(
              kNames[c],
              Imf::Slice(Imf::FLOAT,
                         reinterpret_cast<char*>(const_cast<float*>(image.texels.data()) + c),
                         x_stride, x_stride * image.width));
        }
        file.setFrameBuffer(frame_buffer);
        file.writePixels(static_cast<int>(image.height));
      }
      bytes = stream.take();
    } catch (const std::exception& e) {
      return internal_error(std::string("writing the atlas EXR: ") + e.what());
    }
  }
  metadata.set_total_bytes(bytes.size());
  return bytes;
}

}  // namespace ddgi::service
