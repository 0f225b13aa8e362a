#include "server/decode_errors.h"

#include "absl/strings/str_cat.h"
#include "google/protobuf/descriptor.h"

namespace femsimp::server {
namespace {

using grpc::experimental::InterceptionHookPoints;

class UndecodableRequestInterceptor final : public grpc::experimental::Interceptor {
 public:
  explicit UndecodableRequestInterceptor(std::string method) : method_(std::move(method)) {}

  void Intercept(grpc::experimental::InterceptorBatchMethods* methods) override {
    // A unary call's request is decoded before the handler; no message here means it failed
    // (or the client sent none, which gRPC's clients cannot do).
    if (methods->QueryInterceptionHookPoint(InterceptionHookPoints::POST_RECV_MESSAGE) &&
        methods->GetRecvMessage() == nullptr)
      undecodable_ = true;
    if (undecodable_ &&
        methods->QueryInterceptionHookPoint(InterceptionHookPoints::PRE_SEND_STATUS) &&
        methods->GetSendStatus().error_code() == grpc::StatusCode::INTERNAL) {
      const std::string type = RequestTypeName(method_);
      methods->ModifySendStatus(
          grpc::Status(grpc::StatusCode::INVALID_ARGUMENT,
                       absl::StrCat("the request to ", method_, " could not be decoded as ",
                                    type.empty() ? std::string("its request message") : type,
                                    " (not a serialized protobuf message of that type)")));
    }
    methods->Proceed();
  }

 private:
  const std::string method_;
  bool undecodable_ = false;
};

}  // namespace

std::string RequestTypeName(const std::string& method) {
  // "/package.Service/Method" -> "package.Service.Method"
  if (method.size() < 2 || method[0] != '/') return "";
  std::string name = method.substr(1);
  const size_t slash = name.find('/');
  if (slash == std::string::npos) return "";
  name[slash] = '.';
  const google::protobuf::MethodDescriptor* m =
      google::protobuf::DescriptorPool::generated_pool()->FindMethodByName(name);
  return m != nullptr ? m->input_type()->full_name() : "";
}

grpc::experimental::Interceptor* UndecodableRequestInterceptorFactory::CreateServerInterceptor(
    grpc::experimental::ServerRpcInfo* info) {
  if (info->type() != grpc::experimental::ServerRpcInfo::Type::UNARY) return nullptr;
  return new UndecodableRequestInterceptor(info->method());
}

}  // namespace femsimp::server
