// The request fuzzer's input format, shared by the fuzzer (fuzz_requests.cpp) and the seed
// writer (request_seeds.cpp): one byte choosing the RPC (kMethods, modulo its size), one byte
// of flags, then the request message's protobuf bytes. The flags let short inputs reach a live
// session, view and light, which random bytes could never name; without them the ids in the
// message are used as they are.
#pragma once

#include <array>
#include <cstdint>
#include <string_view>

namespace ddgi::fuzz {

// Every RPC of ddgi.v1.RenderService, in the order the input's first byte counts them.
inline constexpr std::array<std::string_view, 22> kMethods = {
    "GetServerInfo",  "CreateSession",
    "LoadScene",      "CloseSession",
    "ListSessions",   "GetSession",
    "CreateView",     "UpdateView",
    "DeleteView",     "SetCamera",
    "AddLight",       "UpdateLight",
    "RemoveLight",    "SetInstanceTransform",
    "GetFieldParams", "SetFieldParams",
    "RenderFrame",    "StreamFrames",
    "DumpAtlas",      "QueryIrradiance",
    "StreamProbes",   "ExportScene"};

enum InputFlag : uint8_t {
  kLiveSession = 1,  // session_id := the live session's
  kLiveView = 2,     // view_id := a view of the live session
  kNoToken = 4,      // send no bearer token (the server requires one)
};

}  // namespace ddgi::fuzz
