#include "client/run_input.h"

#include <cstdio>
#include <string>

#include "engine/io/mesh_io.h"

namespace femsimp::cli {

RunReport StartReport(const SimplifyArgs& args) {
  RunReport report;
  report.input_path = args.input;
  report.output_path = args.output;
  report.options = args.options;
  report.server = args.server;
  return report;
}

std::optional<RawMesh> ReadInput(const SimplifyArgs& args, RunReport& report) {
  absl::StatusOr<RawMesh> raw = ReadMeshFile(args.input);
  if (!raw.ok()) {
    std::fprintf(stderr, "femsimp: cannot read %s: %s\n", args.input.c_str(),
                 std::string(raw.status().message()).c_str());
    return std::nullopt;
  }
  report.input_vertices = raw->num_vertices();
  report.input_faces = raw->num_faces();
  return *std::move(raw);
}

double SecondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace femsimp::cli
