// atlas_convert.h for ddgi-client-lean, the build without OpenImageIO (GPU hosts, containers):
// dumps are still written as received; converting them needs the full ddgi-client.
#include "atlas_convert.h"

namespace ddgi::client {

Result<AtlasTexels> atlas_texels(const v1::AtlasMetadata&, const std::string&, const std::string&) {
  return failed_precondition(
      "this ddgi-client-lean has no OpenImageIO: --convert needs the full ddgi-client");
}

Status convert_atlas(const AtlasTexels&, v1::AtlasKind, const std::string&) {
  return failed_precondition(
      "this ddgi-client-lean has no OpenImageIO: --convert needs the full ddgi-client");
}

}  // namespace ddgi::client
