// A request gRPC cannot decode must get an answer that says so (issue 15, item 6): for a unary
// method gRPC itself answers INTERNAL with an empty message before any handler runs; this server
// interceptor turns that into INVALID_ARGUMENT naming the message type the method takes.
// (A streaming read that cannot decode ends the stream like a half-close; RequestReader's messages
// name both causes.)
#pragma once

#include <string>

#include "grpcpp/support/server_interceptor.h"

namespace femsimp::server {

class UndecodableRequestInterceptorFactory final
    : public grpc::experimental::ServerInterceptorFactoryInterface {
 public:
  grpc::experimental::Interceptor* CreateServerInterceptor(
      grpc::experimental::ServerRpcInfo* info) override;
};

// "femsimp.v1.GetJobRequest" for "/femsimp.v1.Simplifier/GetJob": the request type's full name
// from the generated descriptors; "" for a method they do not know.
std::string RequestTypeName(const std::string& method);

}  // namespace femsimp::server
