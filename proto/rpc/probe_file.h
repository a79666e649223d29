// probes.bin: a session's irradiance field in one file, as `ddgi-client probes` writes it and
// `ddgi-client irradiance` and the web client (web/probes.js) read it, so a client can shade
// from the probes without asking the server (docs/probe-files.md has the layout).
#pragma once

#include <cstdint>
#include <string>

#include "core/result.h"
#include "rpc/probe_field.h"

namespace ddgi {

inline constexpr char kProbeFileMagic[9] = "DDGIPRB1";

struct ProbeFile {
  ProbeField field;
  uint64_t field_updates = 0;  // updates the field had run when it was read
  std::string session_id;
};

std::string encode_probe_file(const ProbeFile& file);
// INVALID_ARGUMENT naming what is wrong (magic, header, sizes) for anything else.
Result<ProbeFile> decode_probe_file(const std::string& bytes);

}  // namespace ddgi
