#include "scene/gltf_parse.h"

#include <optional>
#include <string>
#include <system_error>

#include <nlohmann/json.hpp>

#include "scene/accessor_reader.h"
#include "scene/glb_container.h"
#include "scene/gltf_json_check.h"
#include "scene/image_decode.h"
#include "scene/json_precheck.h"

namespace ddgi {
namespace {

// tinygltf reports through C-style callbacks; this keeps the first real error with its code.
struct ParseContext {
  const SceneFolder* folder = nullptr;
  // tinygltf joins this base folder with each URI; what follows it is the URI itself.
  std::string base_prefix;
  uint64_t max_file_bytes = 0;
  // Many URIs may name the same large file: what they read adds up against max_file_bytes.
  uint64_t bytes_read = 0;
  uint32_t max_texture_dimension = 0;
  const tinygltf::Model* model = nullptr;  // buffers and views are parsed before images
  std::optional<Error> first_error;

  void note(Error error) {
    if (!first_error) first_error = std::move(error);
  }
  // The URI inside a path tinygltf built; nullopt for its fallback guesses relative to the
  // process's working directory, which are never allowed.
  std::optional<std::string> uri_of(const std::string& path) const {
    if (path.compare(0, base_prefix.size(), base_prefix) != 0) return std::nullopt;
    return path.substr(base_prefix.size());
  }
};

std::string expand_file_path(const std::string& path, void*) {
  return path;
}

bool file_exists(const std::string& path, void* user) {
  auto* ctx = static_cast<ParseContext*>(user);
  const std::optional<std::string> uri = ctx->uri_of(path);
  if (!uri) return false;
  Result<std::filesystem::path> resolved = ctx->folder->resolve(*uri);
  if (!resolved.ok()) {
    ctx->note(resolved.error());
    return false;
  }
  return true;
}

bool read_whole_file(std::vector<unsigned char>* out, std::string* err, const std::string& path,
                     void* user) {
  auto* ctx = static_cast<ParseContext*>(user);
  const std::optional<std::string> uri = ctx->uri_of(path);
  if (!uri) {
    *err = "refused";
    return false;
  }
  Result<std::filesystem::path> resolved = ctx->folder->resolve(*uri);
  if (!resolved.ok()) {
    ctx->note(resolved.error());
    *err = resolved.error().message;
    return false;
  }
  std::error_code ec;
  const uint64_t size = std::filesystem::file_size(*resolved, ec);
  if (!ec && size > ctx->max_file_bytes - ctx->bytes_read) {
    ctx->note(resource_exhausted("uri '" + *uri +
                                 "': the files this scene references add up to "
                                 "more than the limit of " +
                                 std::to_string(ctx->max_file_bytes) + " bytes"));
    *err = "file size limit";
    return false;
  }
  Result<std::vector<uint8_t>> bytes = read_file(*resolved, ctx->max_file_bytes - ctx->bytes_read);
  if (!bytes.ok()) {
    ctx->note(bytes.error().with_context("uri '" + *uri + "'"));
    *err = bytes.error().message;
    return false;
  }
  ctx->bytes_read += bytes->size();
  *out = std::move(bytes).value();
  return true;
}

bool write_whole_file(std::string* err, const std::string&, const std::vector<unsigned char>&,
                      void*) {
  *err = "the scene loader never writes files";
  return false;
}

std::string image_label(const tinygltf::Image& image, int index) {
  std::string label = "images[" + std::to_string(index) + "]";
  if (!image.name.empty()) label += " '" + image.name + "'";
  return label;
}

// tinygltf's image callback: check the header, keep the bytes; decoding waits until we know
// which images the scene uses. Images in buffer views are not copied (many images may share
// one large view); encoded_image() finds their bytes later.
bool keep_encoded_image(tinygltf::Image* image, const int index, std::string* err, std::string*,
                        int, int, const unsigned char* bytes, int size, void* user) {
  auto* ctx = static_cast<ParseContext*>(user);
  const std::string label = image_label(*image, index);
  std::span<const uint8_t> encoded;
  if (image->bufferView != -1) {
    // tinygltf hands over a pointer without checking the view's range against the buffer.
    Result<std::span<const uint8_t>> view = buffer_view_bytes(*ctx->model, image->bufferView);
    if (!view.ok()) {
      ctx->note(view.error().with_context(label));
      *err += label + ": " + view.error().message + "\n";
      return false;
    }
    encoded = *view;
  } else {
    if (bytes == nullptr || size <= 0) {
      ctx->note(invalid_argument(label + ": empty or oversized image data"));
      *err += label + ": empty or oversized image data\n";
      return false;
    }
    encoded = std::span<const uint8_t>(bytes, static_cast<size_t>(size));
  }
  Result<ImageSize> probed = probe_image(encoded, ctx->max_texture_dimension);
  if (!probed.ok()) {
    ctx->note(probed.error().with_context(label));
    *err += label + ": " + probed.error().message + "\n";
    return false;
  }
  if (image->bufferView == -1) image->image.assign(encoded.begin(), encoded.end());
  image->as_is = true;
  image->width = static_cast<int>(probed->width);
  image->height = static_cast<int>(probed->height);
  image->component = 4;
  image->bits = 8;
  image->pixel_type = TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE;
  return true;
}

// tinygltf copies the whole BIN chunk into every GLB buffer that has no uri, before any check
// of ours could run: a few bytes of JSON listing many such buffers would exhaust memory.
// (check_gltf_json has made sure `buffers` is an array of objects.)
Status check_glb_buffers(const nlohmann::json& doc) {
  const auto buffers = doc.find("buffers");
  if (buffers == doc.end()) return ok_status();
  for (size_t i = 1; i < buffers->size(); ++i) {
    if (!(*buffers)[i].contains("uri")) {
      return invalid_argument("buffers[" + std::to_string(i) +
                              "] has no uri; only buffers[0] may refer to the GLB BIN chunk");
    }
  }
  return ok_status();
}

std::string trim(std::string text) {
  while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.pop_back();
  return text;
}

// Every image must have arrived: tinygltf only warns when an image file is missing.
Status check_images_loaded(const tinygltf::Model& model, const ParseContext& ctx) {
  for (size_t i = 0; i < model.images.size(); ++i) {
    const tinygltf::Image& image = model.images[i];
    if (image.as_is) continue;
    if (ctx.first_error) return ctx.first_error->with_context(image_label(image, int(i)));
    return invalid_argument(image_label(image, static_cast<int>(i)) +
                            ": no image data (neither a loadable uri nor a bufferView)");
  }
  return ok_status();
}

}  // namespace

std::span<const uint8_t> encoded_image(const tinygltf::Model& model, const tinygltf::Image& image) {
  if (image.bufferView == -1) return image.image;
  Result<std::span<const uint8_t>> view = buffer_view_bytes(model, image.bufferView);
  return view.ok() ? *view : std::span<const uint8_t>();
}

Result<tinygltf::Model> parse_gltf(std::span<const uint8_t> bytes, const SceneFolder& folder,
                                   const SceneLimits& limits) {
  const bool binary = has_glb_magic(bytes);
  std::span<const uint8_t> json_text = bytes;
  if (binary) {
    DDGI_ASSIGN_OR_RETURN(const GlbChunks chunks, parse_glb_container(bytes));
    json_text = chunks.json;
  }
  if (json_text.size() < 2) return invalid_argument("the file is too short to be glTF");
  DDGI_TRY(precheck_json(json_text, limits.max_json_depth));
  {
    // The pre-check bounded the nesting, so the document can be built; it is dropped before
    // tinygltf builds its own.
    const nlohmann::json doc = nlohmann::json::parse(json_text.begin(), json_text.end(), nullptr,
                                                     /*allow_exceptions=*/false);
    if (doc.is_discarded()) return invalid_argument("invalid JSON");
    DDGI_TRY(check_gltf_json(doc));
    if (binary) DDGI_TRY(check_glb_buffers(doc));
  }

  ParseContext ctx;
  ctx.folder = &folder;
  // A base that cannot be a real folder when there is none: every URI then reaches
  // SceneFolder::resolve, which refuses it with a clear message.
  const std::string base_dir = folder.allows_files() ? folder.root().string() : "<uploaded>";
  ctx.base_prefix = base_dir.back() == '/' ? base_dir : base_dir + "/";
  ctx.max_file_bytes = limits.max_file_bytes;
  ctx.max_texture_dimension = limits.max_texture_dimension;

  tinygltf::Model model;
  ctx.model = &model;
  tinygltf::TinyGLTF loader;
  loader.SetFsCallbacks(tinygltf::FsCallbacks{&file_exists, &expand_file_path, &read_whole_file,
                                              &write_whole_file, &ctx});
  loader.SetImageLoader(&keep_encoded_image, &ctx);

  std::string err;
  std::string warn;
  bool parsed = false;
  try {
    if (binary) {
      parsed = loader.LoadBinaryFromMemory(&model, &err, &warn, bytes.data(),
                                           static_cast<unsigned int>(bytes.size()), base_dir);
    } else {
      parsed = loader.LoadASCIIFromString(&model, &err, &warn,
                                          reinterpret_cast<const char*>(json_text.data()),
                                          static_cast<unsigned int>(json_text.size()), base_dir);
    }
  } catch (const std::exception& e) {
    return invalid_argument(std::string("glTF parser failed: ") + e.what());
  } catch (...) {
    return invalid_argument("glTF parser failed with an unknown exception");
  }
  if (!parsed) {
    if (ctx.first_error) return *ctx.first_error;
    return invalid_argument("invalid glTF: " + trim(err.empty() ? "unknown parse error" : err));
  }
  DDGI_TRY(check_images_loaded(model, ctx));
  return model;
}

}  // namespace ddgi
