#include "service/web_scene_download.h"

#include <civetweb.h>

#include <cstring>
#include <string>

#include "rpc/chunk_download.h"
#include "rpc/status_code_name.h"

namespace ddgi::service {
namespace {

int http_status(grpc::StatusCode code) {
  switch (code) {
    case grpc::StatusCode::INVALID_ARGUMENT:
      return 400;
    case grpc::StatusCode::UNAUTHENTICATED:
      return 401;
    case grpc::StatusCode::PERMISSION_DENIED:
      return 403;
    case grpc::StatusCode::NOT_FOUND:
      return 404;
    case grpc::StatusCode::RESOURCE_EXHAUSTED:
      return 429;
    case grpc::StatusCode::FAILED_PRECONDITION:
      return 409;
    case grpc::StatusCode::UNAVAILABLE:
      return 503;
    default:
      return 500;
  }
}

int refuse(mg_connection* connection, grpc::StatusCode code, const std::string& message) {
  const std::string body = std::string(status_code_name(code)) + ": " + message + "\n";
  const int status = http_status(code);
  mg_response_header_start(connection, status);
  mg_response_header_add(connection, "Content-Type", "text/plain; charset=utf-8", -1);
  mg_response_header_add(connection, "Content-Length", std::to_string(body.size()).c_str(), -1);
  mg_response_header_add(connection, "Cache-Control", "no-store", -1);
  mg_response_header_send(connection);
  mg_write(connection, body.data(), body.size());
  return status;
}

// The request's Authorization header, passed on whole: the service's auth parses and judges it.
std::string authorization_header(mg_connection* connection) {
  const char* header = mg_get_header(connection, "Authorization");
  return header == nullptr ? "" : header;
}

}  // namespace

int serve_scene_download(mg_connection* connection, v1::RenderService::Stub& stub) {
  const mg_request_info* request = mg_get_request_info(connection);
  if (std::string(request->request_method) != "GET") {
    return refuse(connection, grpc::StatusCode::INVALID_ARGUMENT,
                  "only GET /scene.glb?session=ID is served here");
  }
  const char* query = request->query_string ? request->query_string : "";
  char session[256];
  if (mg_get_var(query, std::strlen(query), "session", session, sizeof(session)) <= 0) {
    return refuse(connection, grpc::StatusCode::INVALID_ARGUMENT,
                  "the query needs session=ID (at most 255 bytes)");
  }
  grpc::ClientContext call;
  if (const std::string authorization = authorization_header(connection); !authorization.empty()) {
    call.AddMetadata("authorization", authorization);
  }
  v1::ExportSceneRequest export_request;
  export_request.set_session_id(session);
  auto reader = stub.ExportScene(&call, export_request);
  bool started = false;
  const grpc::Status status = read_chunks<v1::SceneChunk, v1::SceneMetadata>(
      call, *reader,
      [&](const v1::SceneMetadata& metadata) {
        mg_response_header_start(connection, 200);
        mg_response_header_add(connection, "Content-Type", "model/gltf-binary", -1);
        mg_response_header_add(connection, "Content-Length",
                               std::to_string(metadata.total_bytes()).c_str(), -1);
        mg_response_header_add(connection, "Cache-Control", "no-store", -1);
        mg_response_header_send(connection);
        started = true;
        return true;
      },
      [&](const std::string& data) {
        return mg_write(connection, data.data(), data.size()) == int(data.size());
      });
  if (!started) return refuse(connection, status.error_code(), status.error_message());
  // Once the headers are out only the connection's end can tell the browser (the body is short
  // of its Content-Length, which fetch reports as an error).
  return status.ok() ? 200 : 500;
}

}  // namespace ddgi::service
