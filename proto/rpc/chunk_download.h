// Reading a download stream (DumpAtlas, ExportScene) as every client does: the metadata first,
// then the bytes in order up to the announced size. Each piece goes to a callback as it comes,
// so a caller can pass the bytes on (the web front to a browser) or keep them (ddgi-client).
#pragma once

#include <grpcpp/grpcpp.h>

#include <functional>
#include <memory>
#include <string>

namespace ddgi {

// Reads `reader` to its end. `on_metadata(metadata)` once, then `on_data(bytes)` per chunk;
// either returning false cancels the call (CANCELLED). DATA_LOSS when chunks come out of order,
// beyond the announced size, or short of it.
template <typename Chunk, typename Metadata>
grpc::Status read_chunks(grpc::ClientContext& call, grpc::ClientReaderInterface<Chunk>& reader,
                         const std::function<bool(const Metadata&)>& on_metadata,
                         const std::function<bool(const std::string&)>& on_data) {
  Chunk chunk;
  bool have_metadata = false;
  uint64_t total = 0, received = 0;
  auto stop = [&](grpc::Status status) {
    call.TryCancel();
    (void)reader.Finish();
    return status;
  };
  while (reader.Read(&chunk)) {
    if (chunk.has_metadata()) {
      if (have_metadata) return stop(grpc::Status(grpc::StatusCode::DATA_LOSS, "metadata twice"));
      have_metadata = true;
      total = chunk.metadata().total_bytes();
      if (!on_metadata(chunk.metadata())) return stop(grpc::Status::CANCELLED);
      continue;
    }
    if (!have_metadata || chunk.offset() != received || received + chunk.data().size() > total) {
      return stop(grpc::Status(grpc::StatusCode::DATA_LOSS,
                               "chunks out of order or beyond the announced size"));
    }
    received += chunk.data().size();
    if (!on_data(chunk.data())) return stop(grpc::Status::CANCELLED);
  }
  const grpc::Status status = reader.Finish();
  if (!status.ok()) return status;
  if (!have_metadata || received != total) {
    return grpc::Status(grpc::StatusCode::DATA_LOSS, "the download ended after " +
                                                         std::to_string(received) + " of " +
                                                         std::to_string(total) + " bytes");
  }
  return grpc::Status::OK;
}

}  // namespace ddgi
