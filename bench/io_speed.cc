// Mesh files at disk speed (issue 14, item 2): for each mesh, where the time of the CLI's "load"
// goes (read, repair, Mesh::Build), then every format written and read by femsimp and by
// OpenMesh, side by side on the same mesh, interleaved per repeat so that machine noise hits both
// alike (best of the repeats). Files go to a scratch directory and are read back while they are
// in the page cache. MB/s is file bytes / wall seconds, Mtri/s the mesh's triangles / wall
// seconds; "ratio" is OpenMesh's time over femsimp's (above 1: femsimp is faster).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "bench/peers/openmesh_soup.h"
#include "common/flags.h"
#include "engine/io/mesh_io.h"
#include "engine/mesh.h"
#include "engine/repair.h"

namespace {

namespace fs = std::filesystem;
using femsimp::RawMesh;
using femsimp::bench::ToTriMesh;
using femsimp::bench::TriMesh;
using Clock = std::chrono::steady_clock;

struct Args {
  int repeats = 5;
  bool stages_only = false;
  std::string dir = "build/io_speed";
  std::vector<std::string> meshes;
};

struct Format {
  std::string name;  // as printed
  std::string ext;
  bool binary;
  bool openmesh;  // OpenMesh has a reader and writer for it
};

const std::vector<Format>& Formats() {
  static const std::vector<Format> kFormats = {
      {"STL binary", ".stl", true, true}, {"PLY binary", ".ply", true, true},
      {"STL ASCII", ".stl", false, true}, {"PLY ASCII", ".ply", false, true},
      {"OFF", ".off", false, true},       {"OBJ", ".obj", false, true},
      {"MSH 4.1", ".msh", false, false}};
  return kFormats;
}

// Best wall time of one operation over the repeats, and the bytes it moved.
struct Timing {
  double best = 1e300;
  uintmax_t bytes = 0;
  void Add(double s) { best = std::min(best, s); }
};

double Time(const std::function<bool()>& op, bool* ok) {
  const auto t0 = Clock::now();
  *ok = op() && *ok;
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

bool Fail(const std::string& what) {
  std::fprintf(stderr, "io_speed: %s\n", what.c_str());
  return false;
}

// Read, repair and Build of the mesh file as the CLI's "load" runs them (engine/prepare.cc).
bool Stages(const std::string& path, int repeats) {
  Timing read, repair, build;
  bool ok = true;
  for (int r = 0; r < repeats && ok; ++r) {
    std::optional<RawMesh> raw;
    read.Add(Time(
        [&] {
          absl::StatusOr<RawMesh> m = femsimp::ReadMeshFile(path);
          if (!m.ok()) return Fail(std::string(m.status().message()));
          raw = *std::move(m);
          return true;
        },
        &ok));
    if (!ok) break;
    repair.Add(Time(
        [&] {
          absl::StatusOr<femsimp::RepairResult> rr =
              femsimp::RepairMesh(*raw, femsimp::RepairOptions{});
          return rr.ok() || Fail(std::string(rr.status().message()));
        },
        &ok));
    build.Add(Time(
        [&] {
          absl::StatusOr<femsimp::Mesh> m = femsimp::Mesh::Build(*raw);
          return m.ok() || Fail(std::string(m.status().message()));
        },
        &ok));
  }
  if (!ok) return false;
  const double total = read.best + repair.best + build.best;
  std::printf("| %s | %.3f | %.3f | %.3f | %.3f | %.0f %% |\n", fs::path(path).filename().c_str(),
              read.best, repair.best, build.best, total, 100 * build.best / total);
  return true;
}

std::string Rate(const Timing& t, size_t faces) {
  char s[64];
  std::snprintf(s, sizeof(s), "%.0f | %.2f", t.bytes / t.best / 1e6, faces / t.best / 1e6);
  return s;
}

bool Formats(const std::string& path, const Args& args) {
  absl::StatusOr<RawMesh> raw = femsimp::ReadMeshFile(path);
  if (!raw.ok()) return Fail(std::string(raw.status().message()));
  TriMesh om_mesh;
  ToTriMesh(*raw, om_mesh);
  const size_t faces = raw->num_faces();
  const std::string stem = fs::path(path).stem().string();
  struct Row {
    Timing write, read, om_write, om_read;
  };
  std::vector<Row> rows(Formats().size());
  bool ok = true;
  for (int r = 0; r < args.repeats && ok; ++r) {
    for (size_t i = 0; i < Formats().size() && ok; ++i) {
      const Format& f = Formats()[i];
      const std::string tag = stem + (f.binary ? "_bin" : "_txt");
      const std::string mine = args.dir + "/" + tag + f.ext;
      const std::string theirs = args.dir + "/" + tag + "_openmesh" + f.ext;
      Row& row = rows[i];
      row.write.Add(Time(
          [&] {
            absl::Status s = f.binary ? femsimp::WriteMeshFile(mine, *raw)
                                      : femsimp::WriteMeshFileAscii(mine, *raw);
            return s.ok() || Fail(std::string(s.message()));
          },
          &ok));
      row.read.Add(Time(
          [&] {
            absl::StatusOr<RawMesh> m = femsimp::ReadMeshFile(mine);
            return m.ok() || Fail(std::string(m.status().message()));
          },
          &ok));
      row.write.bytes = row.read.bytes = fs::file_size(mine);
      if (!f.openmesh) continue;
      const OpenMesh::IO::Options opt =
          f.binary ? OpenMesh::IO::Options::Binary : OpenMesh::IO::Options::Default;
      row.om_write.Add(Time(
          [&] {
            return OpenMesh::IO::write_mesh(om_mesh, theirs, opt) ||
                   Fail("OpenMesh cannot write " + theirs);
          },
          &ok));
      row.om_read.Add(Time(
          [&] {
            TriMesh m;
            OpenMesh::IO::Options in_opt = opt;
            return OpenMesh::IO::read_mesh(m, theirs, in_opt) ||
                   Fail("OpenMesh cannot read " + theirs);
          },
          &ok));
      row.om_write.bytes = row.om_read.bytes = fs::file_size(theirs);
    }
  }
  if (!ok) return false;
  for (size_t i = 0; i < Formats().size(); ++i) {
    const Format& f = Formats()[i];
    const Row& row = rows[i];
    const std::pair<const Timing*, const Timing*> dirs[2] = {{&row.read, &row.om_read},
                                                             {&row.write, &row.om_write}};
    for (int d = 0; d < 2; ++d) {
      const Timing& mine = *dirs[d].first;
      const Timing& theirs = *dirs[d].second;
      std::printf("| %s | %s | %s | %.1f | %s | ", stem.c_str(), f.name.c_str(),
                  d == 0 ? "read" : "write", mine.bytes / 1e6, Rate(mine, faces).c_str());
      if (f.openmesh)
        std::printf("%s | %.2f |\n", Rate(theirs, faces).c_str(), theirs.best / mine.best);
      else
        std::printf("— | — | — |\n");
    }
  }
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  Args args;
  femsimp::flags::FlagSet set("io_speed");
  set.Number({.name = "--repeats",
              .metavar = "N",
              .help = "repetitions, interleaved (the best counts)",
              .kind = femsimp::flags::NumberKind::kInteger,
              .range = femsimp::Range::Closed(1, 1000),
              .default_text = "5"},
             &args.repeats);
  set.String("--dir", "DIR", "scratch directory for the files (default build/io_speed)", &args.dir);
  set.Switch("--stages-only", "the load's stages only, no formats (e.g. under a profiler)",
             &args.stages_only);
  femsimp::flags::FlagSet::Parsed parsed;
  if (std::optional<int> exit =
          set.ParseMain(argc, argv, "Usage: io_speed [flags] MESH...\n\n", "", &parsed))
    return *exit;
  args.meshes = parsed.positional;
  if (args.meshes.empty()) {
    std::fprintf(stderr, "io_speed: needs at least one MESH (see --help)\n");
    return femsimp::flags::kUsageExit;
  }
  std::error_code ec;
  fs::create_directories(args.dir, ec);
  if (ec) return Fail("cannot create " + args.dir + ": " + ec.message()) ? 0 : 1;

  std::printf("Load stages, best of %d (seconds)\n\n", args.repeats);
  std::printf("| mesh | read | repair | Mesh::Build | total | Build's share |\n");
  std::printf("|---|---|---|---|---|---|\n");
  for (const std::string& m : args.meshes)
    if (!Stages(m, args.repeats)) return 1;
  if (args.stages_only) return 0;
  std::printf("\nFormats, best of %d, interleaved; ratio = OpenMesh time / femsimp time\n\n",
              args.repeats);
  std::printf(
      "| mesh | format | direction | MB | femsimp MB/s | femsimp Mtri/s | OpenMesh MB/s | "
      "OpenMesh Mtri/s | ratio |\n|---|---|---|---|---|---|---|---|---|\n");
  for (const std::string& m : args.meshes)
    if (!Formats(m, args)) return 1;
  return 0;
}
