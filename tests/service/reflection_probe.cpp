#include "tests/service/reflection_probe.h"

#include <grpcpp/generic/generic_stub.h>

#include <chrono>
#include <vector>

namespace ddgi::test {
namespace {

// Waits for the completion of `tag` (operations are started one at a time, so it is next).
bool wait_for(grpc::CompletionQueue& cq, void* tag) {
  void* got = nullptr;
  bool ok = false;
  while (cq.Next(&got, &ok)) {
    if (got == tag) return ok;
  }
  return false;
}

void* tag(intptr_t n) {
  return reinterpret_cast<void*>(n);
}

}  // namespace

ReflectionAnswer list_services(const std::shared_ptr<grpc::Channel>& channel) {
  grpc::GenericStub generic(channel);
  grpc::ClientContext ctx;
  ctx.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(30));
  grpc::CompletionQueue cq;
  auto call = generic.PrepareCall(
      &ctx, "/grpc.reflection.v1alpha.ServerReflection/ServerReflectionInfo", &cq);
  call->StartCall(tag(1));
  ReflectionAnswer answer;
  bool answered = false;
  if (wait_for(cq, tag(1))) {
    // ServerReflectionRequest { list_services = "" }: field 7, length-delimited, empty.
    const char request_bytes[] = {0x3a, 0x00};
    grpc::Slice slice(request_bytes, sizeof(request_bytes));
    grpc::ByteBuffer request(&slice, 1);
    call->Write(request, tag(2));
    if (wait_for(cq, tag(2))) {
      grpc::ByteBuffer response;
      call->Read(&response, tag(3));
      if (wait_for(cq, tag(3))) {
        std::vector<grpc::Slice> slices;
        if (response.Dump(&slices).ok()) {
          for (const auto& s : slices) {
            answer.text.append(reinterpret_cast<const char*>(s.begin()), s.size());
          }
        }
        answered = true;
        ctx.TryCancel();  // one answer is all this asks for
      }
    }
  }
  grpc::Status status;
  call->Finish(&status, tag(4));
  (void)wait_for(cq, tag(4));
  cq.Shutdown();
  void* ignored;
  bool ok;
  while (cq.Next(&ignored, &ok)) {
  }
  answer.status = answered ? grpc::Status::OK : status;
  return answer;
}

}  // namespace ddgi::test
