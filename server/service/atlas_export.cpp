#include "service/atlas_export.h"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfIO.h>
#include <ImfOutputFile.h>
#include <ImfStringAttribute.h>

#include <cstring>
#include <exception>
#include <string>

#include "shared/field_data.h"

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

v1::AtlasMetadata atlas_metadata(const IrradianceField& field, v1::AtlasKind kind,
                                 v1::AtlasFormat format, const IrradianceField::AtlasImage& image) {
  const IrradianceFieldParams& p = field.params();
  const AtlasLayout layout = atlas_layout(p);
  v1::AtlasMetadata m;
  m.set_kind(kind);
  m.set_format(format);
  m.set_width(image.width);
  m.set_height(image.height);
  m.set_probe_counts_x(p.counts.x);
  m.set_probe_counts_y(p.counts.y);
  m.set_probe_counts_z(p.counts.z);
  auto* origin = m.mutable_grid_origin();
  origin->set_x(p.origin.x);
  origin->set_y(p.origin.y);
  origin->set_z(p.origin.z);
  auto* spacing = m.mutable_probe_spacing();
  spacing->set_x(p.spacing.x);
  spacing->set_y(p.spacing.y);
  spacing->set_z(p.spacing.z);
  m.set_border_texels(gpu::kAtlasBorder);
  m.set_tiles_per_row(layout.tiles_per_row);
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

Result<std::vector<uint8_t>> encode_atlas(const IrradianceField::AtlasImage& image,
                                          v1::AtlasMetadata& metadata) {
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
