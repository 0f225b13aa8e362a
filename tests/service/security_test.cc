// Transport security and tenants (issue 15): TLS and mutual TLS from PEM files, plaintext kept
// to loopback addresses, bearer tokens naming tenants that see only their own jobs.
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>

#include "absl/strings/str_cat.h"
#include "client/channel_security.h"
#include "server/auth.h"
#include "server/transport_security.h"
#include "tests/service/test_util.h"
#include "tests/support/files.h"

namespace femsimp {
namespace {

using testing::InProcessServer;

void WriteFile(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

// A CA, a server certificate for localhost / 127.0.0.1 and a client certificate, by openssl.
class Certificates : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new std::string(testing::MakeTempDir("femsimp_tls"));
    const std::string d = *dir_;
    const std::string script = absl::StrCat(
        "set -e; cd ", d, "; exec >openssl.log 2>&1;",
        "openssl req -x509 -newkey ec -pkeyopt ec_paramgen_curve:prime256v1 -nodes -days 2 "
        "-subj /CN=femsimp-test-ca -keyout ca.key -out ca.pem;",
        "for who in server client; do",
        "  openssl req -newkey ec -pkeyopt ec_paramgen_curve:prime256v1 -nodes "
        "-subj /CN=$who -keyout $who.key -out $who.csr;",
        "  printf 'subjectAltName=DNS:localhost,IP:127.0.0.1\\n' > $who.ext;",
        "  openssl x509 -req -in $who.csr -CA ca.pem -CAkey ca.key -CAcreateserial -days 2 "
        "-extfile $who.ext -out $who.pem;",
        "done");
    ASSERT_EQ(std::system(script.c_str()), 0) << "openssl failed, see " << d << "/openssl.log";
  }
  static std::string File(const std::string& name) { return absl::StrCat(*dir_, "/", name); }

  static server::ServerConfig TlsConfig() {
    server::ServerConfig c = testing::TestConfig();
    c.tls_cert_file = File("server.pem");
    c.tls_key_file = File("server.key");
    return c;
  }
  static cli::ChannelSecurity Client(bool client_certificate, const std::string& token = "") {
    cli::SecurityFlags f;
    f.tls_ca_file = File("ca.pem");
    if (client_certificate) {
      f.tls_cert_file = File("client.pem");
      f.tls_key_file = File("client.key");
    }
    absl::StatusOr<cli::ChannelSecurity> s = cli::ResolveSecurity(f);
    EXPECT_TRUE(s.ok()) << s.status();
    s->token = token;
    return *s;
  }

  static std::string* dir_;
};
std::string* Certificates::dir_ = nullptr;

grpc::Status Info(const std::shared_ptr<grpc::Channel>& channel) {
  auto stub = v1::Simplifier::NewStub(channel);
  grpc::ClientContext ctx;
  ctx.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(10));
  v1::ServerInfoResponse info;
  return stub->ServerInfo(&ctx, v1::ServerInfoRequest(), &info);
}

cli::RemoteOutcome RunJob(const std::shared_ptr<grpc::Channel>& channel) {
  auto stub = v1::Simplifier::NewStub(channel);
  grpc::ClientContext ctx;
  ctx.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(60));
  return cli::RemoteSimplify(*stub, ctx, testing::RatioSpec(0.5), testing::MakeTorus(12, 8));
}

TEST_F(Certificates, TlsServesVerifiedClientsOnly) {
  InProcessServer s(TlsConfig());
  const std::string address = s.address();
  EXPECT_TRUE(Info(cli::MakeChannel(address, Client(false))).ok());
  const cli::RemoteOutcome job = RunJob(cli::MakeChannel(address, Client(false)));
  EXPECT_TRUE(job.status.ok()) << job.status.error_message();
  EXPECT_GT(job.output.num_faces(), 0u);
  // A plaintext client gets no connection.
  EXPECT_EQ(Info(cli::MakeChannel(address)).error_code(), grpc::StatusCode::UNAVAILABLE);
  // A client that trusts another CA refuses the server's certificate.
  cli::ChannelSecurity wrong = Client(false);
  cli::SecurityFlags other;
  other.tls_ca_file = File("client.pem");  // not a CA of the server's chain
  wrong.credentials = cli::ResolveSecurity(other)->credentials;
  EXPECT_EQ(Info(cli::MakeChannel(address, wrong)).error_code(), grpc::StatusCode::UNAVAILABLE);
}

TEST_F(Certificates, MutualTlsRequiresAClientCertificate) {
  server::ServerConfig c = TlsConfig();
  c.tls_client_ca_file = File("ca.pem");
  InProcessServer s(c);
  EXPECT_TRUE(Info(cli::MakeChannel(s.address(), Client(true))).ok());
  EXPECT_EQ(Info(cli::MakeChannel(s.address(), Client(false))).error_code(),
            grpc::StatusCode::UNAVAILABLE);
}

TEST_F(Certificates, BadTlsSettingsAreRefusedNamingTheFlag) {
  server::ServerConfig c = testing::TestConfig();
  c.tls_cert_file = File("server.pem");
  server::FemsimpServer only_cert(c);
  absl::Status s = only_cert.Start();
  EXPECT_NE(s.message().find("--tls_key_file"), std::string::npos) << s;
  c.tls_key_file = File("missing.key");
  server::FemsimpServer missing(c);
  s = missing.Start();
  EXPECT_NE(s.message().find("cannot read"), std::string::npos) << s;
  c = testing::TestConfig();
  c.tls_client_ca_file = File("ca.pem");
  server::FemsimpServer ca_alone(c);
  s = ca_alone.Start();
  EXPECT_NE(s.message().find("--tls_client_ca_file needs"), std::string::npos) << s;
}

TEST(TransportSecurity, PlaintextOnlyOnLoopbackUnlessAllowed) {
  EXPECT_TRUE(server::IsLocalAddress("127.0.0.1:50051"));
  EXPECT_TRUE(server::IsLocalAddress("localhost:1"));
  EXPECT_TRUE(server::IsLocalAddress("[::1]:1"));
  EXPECT_TRUE(server::IsLocalAddress("unix:/tmp/femsimp.sock"));
  EXPECT_FALSE(server::IsLocalAddress("0.0.0.0:50051"));
  EXPECT_FALSE(server::IsLocalAddress("[::]:50051"));
  EXPECT_FALSE(server::IsLocalAddress("femsimp.example:50051"));
  server::ServerConfig c = testing::TestConfig();
  c.listen = "0.0.0.0:0";
  absl::StatusOr<std::shared_ptr<grpc::ServerCredentials>> refused =
      server::ListeningCredentials(c);
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(refused.status().message().find("--plaintext_remote"), std::string::npos);
  c.plaintext_remote = true;
  EXPECT_TRUE(server::ListeningCredentials(c).ok());
  EXPECT_EQ(server::TransportDescription(c), "plaintext on a remote address (--plaintext_remote)");
}

TEST(Tokens, ParseTheStaticTokenFileFormat) {
  absl::StatusOr<server::TokenAuthenticator> auth = server::TokenAuthenticator::Parse(
      "# comment\n\nsecret-a,alice,uid1,\"group1,group2\"\n secret-b , \"bob\"\nsecret-c,alice\n",
      "tokens.csv");
  ASSERT_TRUE(auth.ok()) << auth.status();
  EXPECT_EQ(auth->tenants(), 2u);
  absl::StatusOr<server::TokenAuthenticator> bad =
      server::TokenAuthenticator::Parse("ok,alice\nsecret-only\n", "tokens.csv");
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.status().message().find("tokens.csv:2"), std::string::npos) << bad.status();
  EXPECT_EQ(bad.status().message().find("secret-only"), std::string::npos) << "token echoed";
  bad = server::TokenAuthenticator::Parse("t,alice\nt,bob\n", "tokens.csv");
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.status().message().find("tokens.csv:2: a token given twice"), std::string::npos);
  EXPECT_FALSE(server::TokenAuthenticator::Parse("# none\n", "empty.csv").ok());
}

TEST(Tenants, SeeReadAndCancelOnlyTheirOwnJobs) {
  const std::string dir = testing::MakeTempDir("femsimp_tokens");
  WriteFile(dir + "/tokens.csv", "token-alice,alice\ntoken-bob,bob\n");
  server::ServerConfig c = testing::TestConfig();
  c.auth_tokens_file = dir + "/tokens.csv";
  InProcessServer s(c);
  const auto as = [&](const std::string& token) {
    cli::ChannelSecurity security;
    security.token = token;
    return cli::MakeChannel(s.address(), security);
  };
  EXPECT_EQ(Info(cli::MakeChannel(s.address())).error_code(), grpc::StatusCode::UNAUTHENTICATED);
  EXPECT_EQ(Info(as("token-mallory")).error_code(), grpc::StatusCode::UNAUTHENTICATED);
  EXPECT_EQ(RunJob(cli::MakeChannel(s.address())).status.error_code(),
            grpc::StatusCode::UNAUTHENTICATED);

  const cli::RemoteOutcome job = RunJob(as("token-alice"));
  ASSERT_TRUE(job.status.ok()) << job.status.error_message();
  auto alice = v1::Simplifier::NewStub(as("token-alice"));
  auto bob = v1::Simplifier::NewStub(as("token-bob"));
  EXPECT_TRUE(testing::GetJob(*alice, job.job_id).has_value());
  EXPECT_FALSE(testing::GetJob(*bob, job.job_id).has_value());
  const auto list = [](v1::Simplifier::Stub& stub) {
    grpc::ClientContext ctx;
    v1::ListJobsRequest req;
    req.set_include_finished(true);
    v1::ListJobsResponse resp;
    EXPECT_TRUE(stub.ListJobs(&ctx, req, &resp).ok());
    return resp.jobs_size();
  };
  EXPECT_EQ(list(*alice), 1);
  EXPECT_EQ(list(*bob), 0);
  grpc::ClientContext ctx;
  v1::CancelJobRequest cancel;
  cancel.set_job_id(job.job_id);
  v1::CancelJobResponse resp;
  const grpc::Status s_cancel = bob->CancelJob(&ctx, cancel, &resp);
  EXPECT_EQ(s_cancel.error_code(), grpc::StatusCode::NOT_FOUND);
  EXPECT_EQ(s_cancel.error_message(), absl::StrCat("no job '", job.job_id, "'"));
}

// One tenant cannot hold every slot: its unfinished jobs are bounded, other tenants go on; the
// job counter carries the tenant.
TEST(Tenants, UnfinishedJobsAreBoundedPerTenant) {
  const std::string dir = testing::MakeTempDir("femsimp_tenant_limit");
  WriteFile(dir + "/tokens.csv", "token-alice,alice\ntoken-bob,bob\n");
  server::ServerConfig c = testing::TestConfig();
  c.auth_tokens_file = dir + "/tokens.csv";
  c.max_jobs_per_tenant = 1;
  InProcessServer s(c);
  const auto as = [&](const std::string& token) {
    cli::ChannelSecurity security;
    security.token = token;
    return cli::MakeChannel(s.address(), security);
  };
  // Alice's first job stays unfinished: its spec is sent, its mesh never comes.
  auto alice = v1::Simplifier::NewStub(as("token-alice"));
  grpc::ClientContext held;
  auto stream = alice->Simplify(&held);
  v1::SimplifyRequest spec;
  *spec.mutable_spec() = testing::RatioSpec(0.5);
  spec.mutable_spec()->set_vertex_count(3);
  spec.mutable_spec()->set_face_count(1);
  ASSERT_TRUE(stream->Write(spec));
  v1::SimplifyResponse accepted;
  ASSERT_TRUE(stream->Read(&accepted));  // registered: Accepted comes once the upload may start
  const cli::RemoteOutcome second = RunJob(as("token-alice"));
  EXPECT_EQ(second.status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
  EXPECT_NE(second.status.error_message().find("--max_jobs_per_tenant"), std::string::npos)
      << second.status.error_message();
  const cli::RemoteOutcome bobs = RunJob(as("token-bob"));
  EXPECT_TRUE(bobs.status.ok()) << bobs.status.error_message();
  held.TryCancel();
  stream->Finish().IgnoreError();
  const std::map<std::string, double> m =
      testing::ParseMetrics(testing::HttpGet(s.server().metrics_port(), "/metrics"));
  EXPECT_EQ(m.count("femsimp_jobs_total{status=\"OK\",tenant=\"bob\"}"), 1u);
  EXPECT_EQ(m.count("femsimp_jobs_total{status=\"RESOURCE_EXHAUSTED\",tenant=\"alice\"}"), 1u);
}

// Tokens ride on TLS the same way.
TEST_F(Certificates, TokensOverTls) {
  const std::string dir = testing::MakeTempDir("femsimp_tokens_tls");
  WriteFile(dir + "/tokens.csv", "token-alice,alice\n");
  server::ServerConfig c = TlsConfig();
  c.auth_tokens_file = dir + "/tokens.csv";
  InProcessServer s(c);
  EXPECT_TRUE(Info(cli::MakeChannel(s.address(), Client(false, "token-alice"))).ok());
  EXPECT_EQ(Info(cli::MakeChannel(s.address(), Client(false))).error_code(),
            grpc::StatusCode::UNAUTHENTICATED);
}

}  // namespace
}  // namespace femsimp
