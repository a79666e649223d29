// GET /scene.glb?session=ID on the web front (docs/web.md, local rendering): the session's
// scene as ExportScene sends it, passed on to the browser chunk by chunk as binary glTF with
// its Content-Length (so the page can show progress). The call goes over the in-process
// channel with the request's bearer token (`Authorization: Bearer ...`), so auth and
// validation are the API's; a refusal is the HTTP status nearest to the gRPC code, with
// "CODE: message" as its text body.
#pragma once

#include "ddgi/v1/render_service.grpc.pb.h"

struct mg_connection;

namespace ddgi::service {

// civetweb's request handler (`stub` as its data); always answers (returns the HTTP status).
int serve_scene_download(mg_connection* connection, v1::RenderService::Stub& stub);

}  // namespace ddgi::service
