#include "engine/repair.h"

#include "engine/mesh_checks.h"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <numeric>
#include <optional>
#include <tuple>
#include <type_traits>
#include <utility>

#include "absl/algorithm/container.h"
#include "absl/container/flat_hash_map.h"
#include "absl/container/flat_hash_set.h"
#include "absl/status/status.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "absl/strings/str_join.h"
#include "engine/box_containment.h"
#include "engine/coordinate_precision.h"
#include "engine/crossings.h"
#include "engine/duplicate_bodies.h"
#include "engine/flat_openings.h"
#include "engine/fold.h"
#include "engine/id_index.h"
#include "engine/least_area_fill.h"
#include "engine/loose_pieces.h"
#include "engine/plane_fill.h"
#include "engine/point_in_shell.h"
#include "engine/repair_imprint.h"
#include "engine/repair_uncross.h"
#include "engine/repair_union.h"
#include "engine/union_find.h"

namespace femsimp {
namespace {

constexpr uint32_t kNoIndex = std::numeric_limits<uint32_t>::max();
// How many unrepairable problems an error lists before "and N more".
constexpr size_t kMaxListedErrors = 20;

struct KindInfo {
  const char* name;
  const char* singular;  // records and errors: "flipped facet 5 at ..."
  const char* plural;
  const char* verb;  // the summary: verb, count, noun, suffix ("flipped 2 facets")
  const char* noun;
  const char* nouns;
  const char* suffix;
};
constexpr KindInfo kKinds[kNumRepairKinds] = {
    {"welded_vertex", "welded vertex", "welded vertices", "welded", "vertex", "vertices", ""},
    {"stitched_edge", "stitched edge", "stitched edges", "stitched", "edge", "edges", ""},
    {"degenerate_facet", "degenerate facet", "degenerate facets", "removed", "degenerate facet",
     "degenerate facets", ""},
    {"split_edge", "split edge", "split edges", "split", "edge at a T-junction",
     "edges at T-junctions", ""},
    {"duplicate_facet", "duplicate facet", "duplicate facets", "removed", "duplicate facet",
     "duplicate facets", ""},
    {"flipped_facet", "flipped facet", "flipped facets", "flipped", "facet", "facets", ""},
    {"reversed_component", "inside-out component", "inside-out components", "turned",
     "inside-out component", "inside-out components", " outward"},
    {"split_vertex", "non-manifold vertex", "non-manifold vertices", "split", "non-manifold vertex",
     "non-manifold vertices", ""},
    {"unreferenced_vertex", "unreferenced vertex", "unreferenced vertices", "dropped",
     "unreferenced vertex", "unreferenced vertices", ""},
    {"filled_hole", "filled hole", "filled holes", "filled", "hole", "holes", ""},
    {"imprinted_contact", "imprinted contact", "imprinted contacts", "imprinted",
     "contact of bodies exported apart", "contacts of bodies exported apart",
     " (re-tiled as one shared surface)"},
    {"unfolded_edge", "folded edge", "folded edges", "unfolded", "folded edge", "folded edges",
     " (two facets lay on each other: the other diagonal taken)"},
    {"crossing_removed", "crossing taken out", "crossings taken out", "took out",
     "patch of crossing facets", "patches of crossing facets", " (their holes closed again)"},
    {"united_bodies", "united bodies", "united bodies", "united", "group of overlapping bodies",
     "groups of overlapping bodies", " (replaced by their union)"},
    {"loose_piece", "loose piece", "loose pieces", "removed", "loose piece", "loose pieces",
     " (open bits beside the bodies)"},
    {"duplicate_body", "duplicate body", "duplicate bodies", "removed", "duplicate body",
     "duplicate bodies", " (closed bodies written twice; the first copy kept)"},
    {"shared_shell", "shared surface", "shared surfaces", "kept", "closed surface two bodies share",
     "closed surfaces two bodies share", " once (each body a part)"},
    {"seam_edge", "non-manifold edge", "non-manifold edges", "kept", "non-manifold edge",
     "non-manifold edges", " as seams"},
    {"non_orientable", "non-orientable component", "non-orientable components", "left",
     "non-orientable component", "non-orientable components", " as they were"},
    {"fold_left", "fold left", "folds left", "left", "folded edge", "folded edges",
     " as they were (two facets lying on each other; FE meshers refuse them)"},
    {"contact_left", "contact left apart", "contacts left apart", "left",
     "contact of bodies exported apart", "contacts of bodies exported apart", " as exported"},
    {"hole_left", "hole left open", "holes left open", "left", "hole", "holes",
     " open (the surface is not closed)"},
    {"crossing_left", "crossing left", "crossings left", "left", "crossing", "crossings",
     " as they were (facets crossing each other; FE meshers refuse them)"},
    {"overlap_left", "overlap left", "overlaps left", "left", "group of overlapping bodies",
     "groups of overlapping bodies", " not united (FE meshers refuse them)"},
    {"shared_shell_left", "shared surface left", "shared surfaces left", "left",
     "closed surface two bodies share", "closed surfaces two bodies share",
     " as cavity walls (the body inside is not in the volume)"},
};

const KindInfo& Info(RepairKind kind) { return kKinds[static_cast<size_t>(kind)]; }

std::string Point(const std::array<double, 3>& p) {
  return absl::StrFormat("(%.9g, %.9g, %.9g)", p[0], p[1], p[2]);
}

struct CellKey {
  int64_t x, y, z;
  bool operator==(const CellKey& o) const { return x == o.x && y == o.y && z == o.z; }
  template <typename H>
  friend H AbslHashValue(H h, const CellKey& k) {
    return H::combine(std::move(h), k.x, k.y, k.z);
  }
};

class Repairer {
 public:
  Repairer(const RawMesh& in, const RepairOptions& options)
      : in_(in), options_(options), strict_(options.mode == RepairMode::kOff) {}

  absl::StatusOr<RepairResult> Run(RawMesh& mesh);

 private:
  const float* Pos(uint32_t v) const { return &in_.positions[3 * size_t(v)]; }
  std::array<double, 3> PosD(uint32_t v) const {
    const float* p = Pos(v);
    return {p[0], p[1], p[2]};
  }
  // A point of the mesh as the file has it, for the user (positions are relative to the origin).
  std::array<double, 3> World(const std::array<double, 3>& p) const {
    return {in_.origin[0] + p[0], in_.origin[1] + p[1], in_.origin[2] + p[2]};
  }
  // (b - a) x (c - a): the facet's normal, twice its area long.
  std::array<double, 3> AreaVector(uint32_t a, uint32_t b, uint32_t c) const {
    const std::array<double, 3> p = PosD(a), q = PosD(b), r = PosD(c);
    const double u[3] = {q[0] - p[0], q[1] - p[1], q[2] - p[2]};
    const double w[3] = {r[0] - p[0], r[1] - p[1], r[2] - p[2]};
    return {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
  }
  std::array<double, 3> Centroid(const uint32_t* t) const {
    std::array<double, 3> c{};
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) c[k] += Pos(t[i])[k] / 3.0;
    return c;
  }
  // Counts one change; records it while under the cap. `detail` is a string or, where the text
  // is costly and changes may number millions, a callable making it.
  template <typename Detail>
  void Record(RepairKind kind, int64_t facet, int64_t vertex, const std::array<double, 3>& at,
              Detail&& detail) {
    size_t& n = result_.report.counts[static_cast<size_t>(kind)];
    if (n++ >= options_.max_records_per_kind) return;
    std::string text;
    if constexpr (std::is_invocable_v<Detail>) {
      text = detail();
    } else {
      text = std::string(detail);
    }
    result_.report.records.push_back({kind, facet, vertex, World(at), std::move(text)});
  }
  // The input vertex a working vertex stands for (split copies: the vertex they were split from).
  uint32_t Origin(uint32_t w) const { return w < nv_ ? w : copy_of_[w - nv_]; }
  // The corner of kept face k at working vertex v (the last corner when v is not on k).
  uint32_t CornerAt(uint32_t k, uint32_t v) const {
    const uint32_t c = 3 * k;
    return tri_[c] == v ? c : tri_[c + 1] == v ? c + 1 : c + 2;
  }

  absl::Status CheckInput() const;
  // The box of the vertices some facet uses (lo > hi: none).
  void ReferencedBox(double lo[3], double hi[3]) const;
  void Weld();
  // Why every facet may have become degenerate: coordinates too coarse where the part lies.
  std::string RoundedAwayNote() const;
  void FilterFacets();
  void CloseTJunctions();
  void BuildEdges();
  // How many kept facets use edge u-v (after BuildEdges).
  uint32_t EdgeUses(uint32_t u, uint32_t v) const;
  // The same for every edge, by edge index (after BuildEdges).
  std::vector<uint32_t> EdgeUseCounts() const;
  bool ZipTJunctions();
  bool FillHoles();
  void PlaceSplitPieces(const std::vector<uint32_t>& after, uint32_t nk0);
  void Orient();
  // The input facet whose group and fields kept facet k carries.
  uint32_t DataSource(uint32_t k) const {
    const auto from = data_from_.find(k);
    return from != data_from_.end() ? from->second : kept_[k];
  }
  void KeepSharedShell(uint32_t seed, const std::vector<uint32_t>& order, uint32_t begin,
                       uint32_t end, const std::vector<uint8_t>& parity, bool keep_seed);
  // Removes the loose pieces (engine/loose_pieces.h); returns whether it removed any (the edges
  // are then stale).
  bool DropLoosePieces();
  // Removes the later copies of closed bodies written twice (engine/duplicate_bodies.h); returns
  // whether it removed any (the edges are then stale).
  bool DropDuplicateBodies();
  // Removes the kept facets marked in `drop`, keeping the others' order.
  void RemoveFacets(const std::vector<uint8_t>& drop);
  // Flips folded edges (engine/fold.h) where that unfolds them (strict: records them), leaving
  // the edges built for what the facets are then.
  void UnfoldEdges();
  void SplitVertices();
  void ReportVertices();
  void ReportEdges();
  void WriteOutput(RawMesh& mesh);
  absl::Status StrictError() const;

  const RawMesh& in_;
  const RepairOptions& options_;
  const bool strict_;
  size_t nv_ = 0, nf_ = 0;
  RepairResult result_;

  std::vector<uint32_t> first_facet_;  // per input vertex: first facet using it, or kNoIndex
  std::vector<uint32_t> rep_;          // per input vertex: the vertex it is welded into
  // Kept faces (in input order): their input facet, and per corner the working vertex (an input
  // vertex, or nv_ + i for split copy i) and the input vertex the file gave.
  std::vector<uint32_t> kept_, tri_, orig_;
  // Undirected edges of the kept faces: edge e owns half-edges ehe_[ebeg_[e] .. ebeg_[e + 1]),
  // half-edge 3k + i running from corner i to corner i + 1 of kept face k (before flips).
  std::vector<uint32_t> ebeg_, ehe_, edge_of_;
  std::vector<uint32_t> edges_from_;  // edges are numbered by lower vertex: v's start at [v]
  std::vector<uint32_t> copy_of_;     // split copy i is a copy of input vertex copy_of_[i]
  // Zero-area facets and needles with three distinct vertices (kOn), for CloseTJunctions to
  // remove.
  std::vector<uint32_t> slivers_;
  // Facets that fill a flat opening as a face group of their own (kept index -> group), and the
  // next such group's id (0: not chosen yet).
  absl::flat_hash_map<uint32_t, uint32_t> own_group_;
  uint32_t next_group_ = 0;
  // Per input vertex: used by a duplicate body's copy that was removed (empty: none was).
  std::vector<uint8_t> went_with_copy_;
  // Per input facet: the later facet with its vertices in the opposite orientation that was
  // removed, or kNoIndex (empty: none was). A closed surface of such facets inside a body is one
  // two bodies share.
  std::vector<uint32_t> twin_;
  // Facets of a shared surface that face as their removed twin did (kept index -> the twin): they
  // carry its group and fields.
  absl::flat_hash_map<uint32_t, uint32_t> data_from_;
};

absl::Status Repairer::CheckInput() const {
  const RawMesh& m = in_;
  if (!(options_.weld_tolerance >= 0 && options_.weld_tolerance < 1))
    return absl::InvalidArgumentError(
        absl::StrCat("weld tolerance ", options_.weld_tolerance,
                     ": must be at least 0 and below 1 (a fraction of the diagonal)"));
  if (m.positions.size() % 3 != 0)
    return absl::InvalidArgumentError(
        absl::StrCat("vertex coordinates: ", m.positions.size(), " is not a multiple of 3"));
  if (m.triangles.size() % 3 != 0)
    return absl::InvalidArgumentError(
        absl::StrCat("triangle indices: ", m.triangles.size(), " is not a multiple of 3"));
  if (nv_ == 0 || nf_ == 0)
    return absl::InvalidArgumentError(
        absl::StrCat("mesh is empty (", nv_, " vertices, ", nf_, " facets)"));
  if (nv_ >= kNoIndex / 2 || 3 * nf_ >= kNoIndex)
    return absl::InvalidArgumentError(
        absl::StrCat("mesh too large: ", nv_, " vertices, ", nf_, " facets"));
  if (!m.face_groups.empty() && m.face_groups.size() != nf_)
    return absl::InvalidArgumentError(
        absl::StrCat("face groups: ", m.face_groups.size(), " ids for ", nf_, " facets"));
  for (const FaceField& field : m.face_fields)
    if (field.values.size() != nf_)
      return absl::InvalidArgumentError(absl::StrCat(
          "face field '", field.name, "': ", field.values.size(), " values for ", nf_, " facets"));
  // List every bad index and every used non-finite vertex: a user fixing the file needs them all.
  std::vector<std::string> problems;
  size_t num_problems = 0;
  auto add = [&](std::string s) {
    if (num_problems++ < kMaxListedErrors) problems.push_back(std::move(s));
  };
  std::vector<uint8_t> reported(nv_, 0);
  for (size_t f = 0; f < nf_; ++f)
    for (int i = 0; i < 3; ++i) {
      const uint32_t v = m.triangles[3 * f + i];
      if (v >= nv_) {
        add(absl::StrCat("facet ", f, " references vertex ", v, " but the mesh has ", nv_,
                         " vertices"));
        continue;
      }
      const float* p = Pos(v);
      if (!reported[v] && !(std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]))) {
        reported[v] = 1;
        add(absl::StrCat("vertex ", v, " (used by facet ", f, ") has a non-finite coordinate (",
                         p[0], ", ", p[1], ", ", p[2], ")"));
      }
    }
  if (num_problems == 0) return absl::OkStatus();
  std::string message =
      absl::StrCat(num_problems, " unrepairable problem", num_problems == 1 ? "" : "s", ": ",
                   absl::StrJoin(problems, "; "));
  if (num_problems > problems.size())
    absl::StrAppend(&message, "; and ", num_problems - problems.size(), " more");
  return absl::InvalidArgumentError(message);
}

// Welds each used vertex into the lowest-numbered earlier representative within the tolerance.
// Only representatives go into the grid, and distances are measured to them, so chains of
// near points do not drift; processing in index order makes the choice deterministic.
void Repairer::Weld() {
  RepairReport& report = result_.report;
  rep_.resize(nv_);
  for (uint32_t v = 0; v < nv_; ++v) rep_[v] = v;
  double lo[3], hi[3];
  ReferencedBox(lo, hi);
  report.diagonal =
      std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                (hi[2] - lo[2]) * (hi[2] - lo[2]));
  if (strict_) return;  // Build accepts coincident vertices: not a defect
  report.weld_tolerance_relative = options_.weld_tolerance;
  const double tol = report.weld_tolerance_relative * report.diagonal;
  report.weld_tolerance_absolute = tol;

  if (!(tol > 0)) {  // exact duplicates only (+0 and -0 alike)
    using Key = std::array<float, 3>;
    const auto key_of = [this](uint32_t v) {
      return Key{Pos(v)[0] + 0.f, Pos(v)[1] + 0.f, Pos(v)[2] + 0.f};
    };
    IdIndex<Key, decltype(key_of)> seen(nv_, key_of);
    for (uint32_t v = 0; v < nv_; ++v)
      if (first_facet_[v] != kNoIndex) rep_[v] = seen.FindOrInsert(key_of(v), v);
    return;
  }
  // A hash on quantised coordinates: cells eight tolerances wide, so that a point's tolerance
  // ball touches 1 cell per axis, 2 with probability 1/4, and about two cells are looked up per
  // point. The index holds each cell's last representative (its cell is computed again from its
  // position), `next` the earlier ones in the same cell.
  const double cell = 8 * tol, tol2 = tol * tol;
  auto index = [&](double x, int k) { return int64_t(std::floor((x - lo[k]) / cell)); };
  const auto cell_of = [&](uint32_t v) {
    const float* p = Pos(v);
    return CellKey{index(p[0], 0), index(p[1], 1), index(p[2], 2)};
  };
  IdIndex<CellKey, decltype(cell_of)> head(nv_, cell_of);
  std::vector<uint32_t> next(nv_, kNoIndex);  // earlier representative in the same cell
  for (uint32_t v = 0; v < nv_; ++v) {
    if (first_facet_[v] == kNoIndex) continue;
    const float* p = Pos(v);
    int64_t a[3], b[3];
    for (int k = 0; k < 3; ++k) {
      a[k] = index(p[k] - tol, k);
      b[k] = index(p[k] + tol, k);
    }
    uint32_t best = kNoIndex;
    for (int64_t x = a[0]; x <= b[0]; ++x)
      for (int64_t y = a[1]; y <= b[1]; ++y)
        for (int64_t z = a[2]; z <= b[2]; ++z)
          for (uint32_t r = head.Find(CellKey{x, y, z}); r != kNoIndex; r = next[r]) {
            const float* q = Pos(r);
            double d2 = 0;
            for (int k = 0; k < 3; ++k) d2 += (double(p[k]) - q[k]) * (double(p[k]) - q[k]);
            if (d2 <= tol2 && r < best) best = r;
          }
    if (best != kNoIndex) {
      rep_[v] = best;
      continue;
    }
    next[v] = head.Exchange(cell_of(v), v);
  }
}

// Removes degenerate facets, then later copies of a facet's vertex set. Copies share their lowest
// vertex: bucketing by it (a counting sort) and sorting each short bucket finds them without a
// hash table of a million triples.
void Repairer::FilterFacets() {
  const std::vector<uint32_t>& t = in_.triangles;
  constexpr uint32_t kKeep = kNoIndex, kRepeats = kNoIndex - 1, kZeroArea = kNoIndex - 2;
  std::vector<uint32_t> fate(nf_, kKeep);  // kKeep, a degenerate kind, or the facet it copies
  std::vector<uint32_t> start(nv_ + 1, 0);
  for (uint32_t f = 0; f < nf_; ++f) {
    const uint32_t* o = &t[3 * size_t(f)];
    const uint32_t w[3] = {rep_[o[0]], rep_[o[1]], rep_[o[2]]};
    if (w[0] == w[1] || w[1] == w[2] || w[0] == w[2]) {
      fate[f] = kRepeats;
      continue;
    }
    // A needle (corners on a line within the weld tolerance) is a sliver as a zero-area facet
    // is: a CAD exporter that writes an edge's midpoint in single precision closes the
    // T-junction there with one, its middle corner off the edge by the rounding, and tetgen
    // aborts on it.
    if (IsZeroArea(Pos(w[0]), Pos(w[1]), Pos(w[2])) ||
        (!strict_ && HeightOverLongestEdge(Pos(w[0]), Pos(w[1]), Pos(w[2])) <=
                         result_.report.weld_tolerance_absolute)) {
      fate[f] = kZeroArea;
      continue;
    }
    ++start[std::min({w[0], w[1], w[2]}) + 1];
  }
  for (size_t v = 0; v < nv_; ++v) start[v + 1] += start[v];
  std::vector<std::array<uint32_t, 3>> bucket(start[nv_]);  // (middle, highest, facet)
  {
    std::vector<uint32_t> fill(start.begin(), start.end() - 1);
    for (uint32_t f = 0; f < nf_; ++f) {
      if (fate[f] != kKeep) continue;
      std::array<uint32_t, 3> w = {rep_[t[3 * size_t(f)]], rep_[t[3 * size_t(f) + 1]],
                                   rep_[t[3 * size_t(f) + 2]]};
      std::sort(w.begin(), w.end());
      bucket[fill[w[0]]++] = {w[1], w[2], f};
    }
  }
  for (size_t v = 0; v < nv_; ++v) {
    if (start[v + 1] - start[v] < 2) continue;
    std::sort(bucket.begin() + start[v], bucket.begin() + start[v + 1]);
    for (uint32_t i = start[v] + 1, first = start[v]; i < start[v + 1]; ++i) {
      if (bucket[i][0] != bucket[first][0] || bucket[i][1] != bucket[first][1]) {
        first = i;
        continue;
      }
      fate[bucket[i][2]] = bucket[first][2];
    }
  }
  kept_.reserve(nf_);
  tri_.reserve(3 * nf_);
  orig_.reserve(3 * nf_);
  for (uint32_t f = 0; f < nf_; ++f) {
    const uint32_t* o = &t[3 * size_t(f)];
    const uint32_t w[3] = {rep_[o[0]], rep_[o[1]], rep_[o[2]]};
    if (fate[f] == kRepeats) {
      const bool before = o[0] == o[1] || o[1] == o[2] || o[0] == o[2];
      Record(RepairKind::kDegenerateFacet, f, -1, Centroid(o), [&] {
        return absl::StrCat(before ? "repeats a vertex" : "two of its corners weld together",
                            " (vertices ", o[0], ", ", o[1], ", ", o[2], ")");
      });
    } else if (fate[f] == kZeroArea) {
      if (strict_) {
        Record(RepairKind::kDegenerateFacet, f, -1, Centroid(w),
               "zero area (its corners lie on a line)");
      } else {
        slivers_.push_back(f);  // recorded with what became of its T-junction
      }
    } else if (fate[f] != kKeep) {
      const uint32_t* first = &t[3 * size_t(fate[f])];
      const uint32_t w0 = rep_[first[0]], w1 = rep_[first[1]];
      // The same cyclic order is the same orientation.
      const bool same =
          (w[0] == w0 && w[1] == w1) || (w[1] == w0 && w[2] == w1) || (w[2] == w0 && w[0] == w1);
      if (!same) {
        twin_.resize(nf_, kNoIndex);
        twin_[fate[f]] = f;
      }
      Record(RepairKind::kDuplicateFacet, f, -1, Centroid(w), [&] {
        return absl::StrCat("same vertices as facet ", fate[f],
                            same ? "" : ", opposite orientation (a zero-volume double wall)");
      });
    } else {
      kept_.push_back(f);
      tri_.insert(tri_.end(), w, w + 3);
      orig_.insert(orig_.end(), o, o + 3);
    }
  }
}

// Removes the zero-area facets with three distinct vertices, first splitting at the middle
// vertex the facets across the longest edge of those that close a T-junction (repair.h). Runs on
// the kept facets before the edges are built; only when there are such slivers, so a mesh
// without any is not touched.
void Repairer::CloseTJunctions() {
  if (slivers_.empty()) return;
  auto key = [](uint32_t u, uint32_t v) {
    return u < v ? uint64_t(u) << 32 | v : uint64_t(v) << 32 | u;
  };
  auto dist2 = [&](uint32_t u, uint32_t v) {
    double d = 0;
    for (int k = 0; k < 3; ++k)
      d += (double(Pos(u)[k]) - Pos(v)[k]) * (double(Pos(u)[k]) - Pos(v)[k]);
    return d;
  };
  enum class Fate { kPending, kCopy, kRemoved, kSplit, kLeftOpen };
  struct Sliver {
    uint32_t facet, a, b, t, ot;  // input facet; working vertices, t's input vertex
    Fate fate = Fate::kPending;
    uint32_t other = kNoIndex;    // kCopy: the sliver it copies
    std::vector<uint32_t> split;  // kSplit: the input facets split
    std::string why;              // kLeftOpen: why not
  };
  std::vector<Sliver> slivers;
  slivers.reserve(slivers_.size());
  absl::flat_hash_map<std::array<uint32_t, 3>, uint32_t> first;  // vertex set -> first sliver
  absl::flat_hash_map<uint64_t, uint32_t> on_edge;               // edge -> pending slivers using it
  for (uint32_t f : slivers_) {
    const uint32_t* o = &in_.triangles[3 * size_t(f)];
    const uint32_t w[3] = {rep_[o[0]], rep_[o[1]], rep_[o[2]]};
    // The longest edge runs from corner i + 1 to i + 2; corner i is the T vertex.
    int i = 0;
    double best = -1;
    for (int j = 0; j < 3; ++j)
      if (const double d = dist2(w[(j + 1) % 3], w[(j + 2) % 3]); d > best) {
        best = d;
        i = j;
      }
    Sliver s;
    s.facet = f;
    s.a = w[(i + 1) % 3];
    s.b = w[(i + 2) % 3];
    s.t = w[i];
    s.ot = o[i];
    std::array<uint32_t, 3> sorted = {w[0], w[1], w[2]};
    std::sort(sorted.begin(), sorted.end());
    if (auto [it, fresh] = first.try_emplace(sorted, uint32_t(slivers.size())); !fresh) {
      s.fate = Fate::kCopy;  // a second copy would keep its edges looking shared
      s.other = slivers[it->second].facet;
    } else {
      for (uint64_t e : {key(s.a, s.b), key(s.a, s.t), key(s.t, s.b)}) ++on_edge[e];
    }
    slivers.push_back(std::move(s));
  }

  // Kept facets by vertex: the input's in one array, those a split gave a vertex in `gained`.
  const uint32_t nk0 = static_cast<uint32_t>(kept_.size());
  std::vector<uint32_t> start(nv_ + 1, 0), by_vertex(tri_.size());
  for (uint32_t v : tri_) ++start[v + 1];
  for (size_t v = 0; v < nv_; ++v) start[v + 1] += start[v];
  {
    std::vector<uint32_t> fill(start.begin(), start.end() - 1);
    for (uint32_t c = 0; c < tri_.size(); ++c) by_vertex[fill[tri_[c]]++] = c / 3;
  }
  absl::flat_hash_map<uint32_t, std::vector<uint32_t>> gained;
  auto has = [&](uint32_t k, uint32_t v) {
    return tri_[3 * k] == v || tri_[3 * k + 1] == v || tri_[3 * k + 2] == v;
  };
  // The kept facets on edge u-v now (a split takes a vertex out of a facet: filtered here).
  auto facets_on = [&](uint32_t u, uint32_t v) {
    std::vector<uint32_t> found;
    for (uint32_t i = start[u]; i < start[u + 1]; ++i)
      if (has(by_vertex[i], u) && has(by_vertex[i], v)) found.push_back(by_vertex[i]);
    if (auto it = gained.find(u); it != gained.end())
      for (uint32_t k : it->second)
        if (has(k, u) && has(k, v)) found.push_back(k);
    std::sort(found.begin(), found.end());
    found.erase(std::unique(found.begin(), found.end()), found.end());
    return found;
  };
  auto uses = [&](uint32_t u, uint32_t v) {  // facets and pending slivers on edge u-v
    auto it = on_edge.find(key(u, v));
    return facets_on(u, v).size() + (it == on_edge.end() ? 0 : it->second);
  };
  // Facet order: a half goes right after the facet it was split from (its first half).
  std::vector<uint32_t> after(nk0, kNoIndex);
  size_t splits = 0;

  // Decides and applies sliver s's fate; s is the only pending sliver on its longest edge.
  auto close = [&](Sliver& s) {
    for (uint64_t e : {key(s.a, s.b), key(s.a, s.t), key(s.t, s.b)}) --on_edge[e];
    const std::vector<uint32_t> across = facets_on(s.a, s.b);
    // Nothing across, or no facet beyond its short edges: removing it opens nothing.
    if (across.empty() || uses(s.a, s.t) + uses(s.t, s.b) == 0) {
      s.fate = Fate::kRemoved;
      return;
    }
    struct Split {
      uint32_t k, x, y, c, corner;  // facet (x, y, c), corner of x in it
    };
    std::vector<Split> plan;
    auto is_long_edge = [&](uint32_t u, uint32_t v) {
      return (u == s.a && v == s.b) || (u == s.b && v == s.a);
    };
    for (uint32_t k : across) {
      uint32_t j = 0;  // the corner where edge a-b starts, in either direction
      while (!is_long_edge(tri_[3 * k + j], tri_[3 * k + (j + 1) % 3])) ++j;
      const Split p{k, tri_[3 * k + j], tri_[3 * k + (j + 1) % 3], tri_[3 * k + (j + 2) % 3],
                    3 * k + j};
      if (IsZeroArea(Pos(p.x), Pos(s.t), Pos(p.c)) || IsZeroArea(Pos(s.t), Pos(p.y), Pos(p.c))) {
        s.fate = Fate::kLeftOpen;
        s.why = absl::StrCat("splitting facet ", kept_[k], " there would give a zero-area facet");
        return;
      }
      if (uses(s.t, p.c) > 0) {
        s.fate = Fate::kLeftOpen;
        s.why = absl::StrCat("splitting facet ", kept_[k], " there would add an edge to vertex ",
                             orig_[3 * k + (j + 2) % 3], " that exists already");
        return;
      }
      plan.push_back(p);
    }
    s.fate = Fate::kSplit;
    for (const Split& p : plan) {
      const uint32_t j = p.corner - 3 * p.k, cy = 3 * p.k + (j + 1) % 3;
      const uint32_t ox = orig_[p.corner], oy = orig_[cy], oc = orig_[3 * p.k + (j + 2) % 3];
      // First half in place, its corners where they were with y's taken by t: (x, t, c); the
      // second, (t, y, c), right after it.
      tri_[cy] = s.t;
      orig_[cy] = s.ot;
      const uint32_t n = static_cast<uint32_t>(kept_.size());
      kept_.push_back(kept_[p.k]);
      tri_.insert(tri_.end(), {s.t, p.y, p.c});
      orig_.insert(orig_.end(), {s.ot, oy, oc});
      after.push_back(after[p.k]);
      after[p.k] = n;
      gained[s.t].push_back(p.k);
      for (uint32_t v : {s.t, p.y, p.c}) gained[v].push_back(n);
      Record(RepairKind::kSplitEdge, kept_[p.k], s.ot, PosD(s.t), [&] {
        const uint32_t* h = &orig_[3 * p.k];
        return absl::StrCat("edge from vertex ", ox, " to vertex ", oy, " split at vertex ", s.ot,
                            " (a T-junction closed by degenerate facet ", s.facet, "): facets (",
                            h[0], ", ", h[1], ", ", h[2], ") and (", s.ot, ", ", oy, ", ", oc, ")");
      });
      s.split.push_back(kept_[p.k]);
      ++splits;
    }
  };

  // In input order; a sliver whose longest edge another pending sliver uses waits for it.
  std::vector<uint32_t> queue;
  absl::flat_hash_map<uint64_t, std::vector<uint32_t>> waiting;  // longest edge -> slivers
  for (uint32_t i = 0; i < slivers.size(); ++i)
    if (slivers[i].fate == Fate::kPending) queue.push_back(i);
  for (size_t qi = 0; qi < queue.size(); ++qi) {
    Sliver& s = slivers[queue[qi]];
    if (on_edge[key(s.a, s.b)] > 1) {
      waiting[key(s.a, s.b)].push_back(queue[qi]);
      continue;
    }
    close(s);
    for (uint64_t e : {key(s.a, s.b), key(s.a, s.t), key(s.t, s.b)})
      if (auto it = waiting.find(e); it != waiting.end() && on_edge[e] <= 1) {
        queue.insert(queue.end(), it->second.begin(), it->second.end());
        waiting.erase(it);
      }
  }
  for (Sliver& s : slivers)
    if (s.fate == Fate::kPending) {  // slivers facing each other across their longest edges
      s.fate = Fate::kLeftOpen;
      s.why = "the other facets on its longest edge have zero area too";
    }

  for (const Sliver& s : slivers) {
    const uint32_t* o = &in_.triangles[3 * size_t(s.facet)];
    const uint32_t w[3] = {rep_[o[0]], rep_[o[1]], rep_[o[2]]};
    Record(RepairKind::kDegenerateFacet, s.facet, -1, Centroid(w), [&] {
      std::string text = IsZeroArea(Pos(w[0]), Pos(w[1]), Pos(w[2]))
                             ? "zero area (its corners lie on a line)"
                             : absl::StrFormat(
                                   "a needle (its corners lie on a line within the weld tolerance: "
                                   "%.3g from it)",
                                   HeightOverLongestEdge(Pos(w[0]), Pos(w[1]), Pos(w[2])));
      switch (s.fate) {
        case Fate::kCopy:
          absl::StrAppend(&text, "; same vertices as facet ", s.other);
          break;
        case Fate::kSplit:
          absl::StrAppend(&text, "; closed a T-junction at vertex ", s.ot, ": split facet",
                          s.split.size() == 1 ? " " : "s ", absl::StrJoin(s.split, ", "), " there");
          break;
        case Fate::kLeftOpen:
          absl::StrAppend(&text, "; not split at its T vertex ", s.ot, ": ", s.why);
          break;
        default:
          break;
      }
      return text;
    });
  }
  if (splits > 0) PlaceSplitPieces(after, nk0);
}

// Puts every split facet's pieces where it stood: facets nk0 and on were appended, after[k]
// being the piece that follows kept facet k (kNoIndex: none).
void Repairer::PlaceSplitPieces(const std::vector<uint32_t>& after, uint32_t nk0) {
  std::vector<uint32_t> kept, tri, orig;
  kept.reserve(kept_.size());
  tri.reserve(tri_.size());
  orig.reserve(orig_.size());
  for (uint32_t k0 = 0; k0 < nk0; ++k0)
    for (uint32_t k = k0; k != kNoIndex; k = after[k]) {
      kept.push_back(kept_[k]);
      tri.insert(tri.end(), &tri_[3 * k], &tri_[3 * k] + 3);
      orig.insert(orig.end(), &orig_[3 * k], &orig_[3 * k] + 3);
    }
  kept_ = std::move(kept);
  tri_ = std::move(tri);
  orig_ = std::move(orig);
}

// Groups half-edges by undirected edge: a counting sort by the lower vertex, then a sort of each
// (short) bucket by the upper one. Linear apart from the buckets of high-valence vertices.
void Repairer::BuildEdges() {
  const uint32_t nh = static_cast<uint32_t>(tri_.size());
  auto ends = [&](uint32_t h, uint32_t* a, uint32_t* b) {
    const uint32_t x = tri_[h], y = tri_[h % 3 == 2 ? h - 2 : h + 1];
    *a = std::min(x, y);
    *b = std::max(x, y);
  };
  std::vector<uint32_t> start(nv_ + 1, 0);
  for (uint32_t h = 0; h < nh; ++h) {
    uint32_t a, b;
    ends(h, &a, &b);
    ++start[a + 1];
  }
  for (size_t v = 0; v < nv_; ++v) start[v + 1] += start[v];
  std::vector<uint64_t> sorted(nh);
  {
    std::vector<uint32_t> fill(start.begin(), start.end() - 1);
    for (uint32_t h = 0; h < nh; ++h) {
      uint32_t a, b;
      ends(h, &a, &b);
      sorted[fill[a]++] = (uint64_t(b) << 32) | h;
    }
  }
  ebeg_.clear();
  ehe_.resize(nh);
  edge_of_.resize(nh);
  for (size_t v = 0; v < nv_; ++v) {
    if (start[v + 1] - start[v] > 1) std::sort(&sorted[start[v]], &sorted[0] + start[v + 1]);
    for (uint32_t i = start[v]; i < start[v + 1]; ++i) {
      if (i == start[v] || (sorted[i] >> 32) != (sorted[i - 1] >> 32)) ebeg_.push_back(i);
      const uint32_t h = uint32_t(sorted[i]);
      ehe_[i] = h;
      edge_of_[h] = uint32_t(ebeg_.size() - 1);
    }
  }
  ebeg_.push_back(nh);
  const uint32_t ne = static_cast<uint32_t>(ebeg_.size() - 1);
  edges_from_.resize(nv_ + 1);
  for (size_t v = 0; v <= nv_; ++v)  // a vertex without edges starts where the next one does
    edges_from_[v] = start[v] < nh ? edge_of_[ehe_[start[v]]] : ne;
}

uint32_t Repairer::EdgeUses(uint32_t u, uint32_t v) const {
  const uint32_t lo = std::min(u, v), hi = std::max(u, v);
  for (uint32_t e = edges_from_[lo]; e < edges_from_[lo + 1]; ++e) {
    const uint32_t h = ehe_[ebeg_[e]];
    const uint32_t other = tri_[h] == lo ? tri_[h % 3 == 2 ? h - 2 : h + 1] : tri_[h];
    if (other == hi) return ebeg_[e + 1] - ebeg_[e];
  }
  return 0;
}

std::vector<uint32_t> Repairer::EdgeUseCounts() const {
  std::vector<uint32_t> uses(ebeg_.size() - 1);
  for (size_t e = 0; e < uses.size(); ++e) uses[e] = ebeg_[e + 1] - ebeg_[e];
  return uses;
}

// Closes the cracks of faces tessellated one by one, as CAD exporters write them: one side of a
// crack has the edge a-b, the other a-m-...-b with its vertices on that segment (a T-junction
// at each) or, along a curve, off it by the chord's sagitta. An open edge is split at the
// vertices of the open edges along it (within an eighth of its length of the segment): its
// facet (a, b, c) becomes the fan (a, m, c), (m, .., c), (.., b, c), with its orientation, group
// and fields; no point moves. A split is made only where some piece then has exactly two facets
// and none more, no piece or fan edge exists already and no piece has zero area or turns
// over; one edge per facet a call. Returns whether it split any (the edges are then stale).
// Whether p lies within `limit` of the segment from a along d (of squared length len2).
bool Within(const std::array<double, 3>& p, const std::array<double, 3>& a,
            const std::array<double, 3>& d, double len2, double limit) {
  double t = 0;
  for (int k = 0; k < 3; ++k) t += (p[k] - a[k]) * d[k];
  t = std::clamp(t / len2, 0.0, 1.0);
  double d2 = 0;
  for (int k = 0; k < 3; ++k) d2 += (p[k] - a[k] - t * d[k]) * (p[k] - a[k] - t * d[k]);
  return d2 <= limit * limit;
}

bool Repairer::ZipTJunctions() {
  const uint32_t ne = static_cast<uint32_t>(ebeg_.size() - 1);
  auto head = [&](uint32_t h) { return tri_[h % 3 == 2 ? h - 2 : h + 1]; };
  std::vector<uint32_t> open;  // one half-edge per open edge
  for (uint32_t e = 0; e < ne; ++e)
    if (ebeg_[e + 1] - ebeg_[e] == 1) open.push_back(ehe_[ebeg_[e]]);
  if (open.empty()) return false;

  auto key = [](uint32_t u, uint32_t v) {
    return u < v ? uint64_t(u) << 32 | v : uint64_t(v) << 32 | u;
  };
  absl::flat_hash_map<uint32_t, std::vector<uint32_t>> open_at;  // vertex -> its open half-edges
  for (uint32_t h : open) {
    open_at[tri_[h]].push_back(h);
    open_at[head(h)].push_back(h);
  }

  // Open vertices by grid cell. Where each face of a part was tessellated on its own, the two
  // sides of a crack share no vertex between the crack's ends: their vertices interleave along
  // it, and no walk along one side's open edges reaches the other's. A cell of the open edges'
  // median length finds them near a segment in a few cells.
  std::vector<double> lengths;
  lengths.reserve(open.size());
  for (uint32_t h : open) {
    const std::array<double, 3> a = PosD(tri_[h]), b = PosD(head(h));
    lengths.push_back(std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                                (a[2] - b[2]) * (a[2] - b[2])));
  }
  std::nth_element(lengths.begin(), lengths.begin() + lengths.size() / 2, lengths.end());
  const double cell = lengths[lengths.size() / 2];
  absl::flat_hash_map<CellKey, std::vector<uint32_t>> grid;
  const auto cell_of = [&](double v) { return static_cast<int64_t>(std::floor(v / cell)); };
  if (cell > 0)
    for (const auto& [v, edges] : open_at) {
      const std::array<double, 3> p = PosD(v);
      grid[CellKey{cell_of(p[0]), cell_of(p[1]), cell_of(p[2])}].push_back(v);
    }

  // Whether an open edge at v runs against direction d, within 30 degrees: the other side of a
  // crack runs back along it (both sides oriented alike), where an open edge that merely passes
  // near (a soup crossing itself, a gap's rim at an angle) runs any way.
  const auto runs_against = [&](uint32_t v, const std::array<double, 3>& d) {
    for (const uint32_t g : open_at[v]) {
      const std::array<double, 3> a = PosD(tri_[g]), b = PosD(head(g));
      double dot = 0, len2 = 0, d2 = 0;
      for (int k = 0; k < 3; ++k) {
        dot += (b[k] - a[k]) * d[k];
        len2 += (b[k] - a[k]) * (b[k] - a[k]);
        d2 += d[k] * d[k];
      }
      if (dot < 0 && dot * dot >= 0.75 * len2 * d2) return true;
    }
    return false;
  };

  struct Plan {
    uint32_t h;                 // open half-edge x -> y of kept facet h / 3
    std::vector<uint32_t> cut;  // the vertices it is split at, from x to y
    std::vector<double> off;    // their distances from the segment x-y
    bool split = false;
  };
  // A crack's vertices along one edge are few; a longer collinear walk is left alone.
  constexpr size_t kMaxWalk = 256;
  // A chord of a circle cut in n is off the arc by about 1/(2n) of its length: 7 and up.
  constexpr double kMaxGapShare = 0.125;
  constexpr double kMaxSpatialShare = 1e-3;
  std::vector<Plan> plans(open.size());
  for (size_t i = 0; i < open.size(); ++i) {
    Plan& plan = plans[i];
    plan.h = open[i];
    const uint32_t x = tri_[plan.h], y = head(plan.h);
    const std::array<double, 3> px = PosD(x), py = PosD(y);
    std::array<double, 3> d;
    double len2 = 0, scale = 0;
    for (int k = 0; k < 3; ++k) {
      d[k] = py[k] - px[k];
      len2 += d[k] * d[k];
      scale = std::max({scale, std::abs(px[k]), std::abs(py[k])});
    }
    const double tol = std::max(result_.report.weld_tolerance_absolute, 2 * FLT_EPSILON * scale);
    const double len = std::sqrt(len2), reach = std::max(tol, kMaxGapShare * len);
    if (!(len > 2 * tol)) continue;
    std::vector<uint32_t> seen = {x, y}, stack = {x, y};
    std::vector<std::array<double, 3>> inner;  // (along, vertex, distance)
    // Takes v if it lies within `limit` of the segment; one inside it, `margin` off its ends, is a
    // cut.
    const auto near = [&](uint32_t v, double limit, double margin) {
      if (std::find(seen.begin(), seen.end(), v) != seen.end()) return false;
      const std::array<double, 3> p = PosD(v);
      double t = 0;
      for (int k = 0; k < 3; ++k) t += (p[k] - px[k]) * d[k];
      t /= len2;
      const double tc = std::clamp(t, 0.0, 1.0);
      double d2 = 0;
      for (int k = 0; k < 3; ++k) d2 += (p[k] - px[k] - tc * d[k]) * (p[k] - px[k] - tc * d[k]);
      if (d2 > limit * limit) return false;
      seen.push_back(v);
      if (t * len > margin && (1 - t) * len > margin)
        inner.push_back({t, double(v), d2 > tol * tol ? std::sqrt(d2) : 0.0});
      return true;
    };
    while (!stack.empty() && seen.size() <= kMaxWalk) {
      const uint32_t u = stack.back();
      stack.pop_back();
      for (uint32_t h : open_at[u]) {
        const uint32_t v = tri_[h] == u ? head(h) : tri_[h];
        if (near(v, reach, reach)) stack.push_back(v);
      }
    }
    // The other side's vertices where they share none with this side near it. Not joined by the
    // crack's walk, they may be a gap's far side (a slot, a hole's other rim): only those within
    // a thousandth of the diagonal are taken, the surface moved no further; one next to an end
    // of this side's is a cut too (the sides interleave), its piece a sliver.
    const double spatial_reach =
        std::min(reach, std::max(4 * tol, kMaxSpatialShare * result_.report.diagonal));
    std::array<int64_t, 3> lo, hi;
    int64_t cells = 1;
    for (int k = 0; k < 3 && cell > 0; ++k) {
      lo[k] = cell_of(std::min(px[k], py[k]) - spatial_reach);
      hi[k] = cell_of(std::max(px[k], py[k]) + spatial_reach);
      cells *= hi[k] - lo[k] + 1;
    }
    // An edge far longer than the others, or a crowd of open vertices around it (a soup of
    // loose facets): the walk alone.
    constexpr int64_t kMaxCells = 512;
    constexpr size_t kMaxScanned = 256;
    size_t scanned = 0;
    if (cell > 0 && cells <= kMaxCells)
      for (int64_t i = lo[0]; i <= hi[0]; ++i)
        for (int64_t j = lo[1]; j <= hi[1]; ++j)
          for (int64_t k = lo[2]; k <= hi[2] && scanned <= kMaxScanned; ++k)
            if (const auto it = grid.find(CellKey{i, j, k}); it != grid.end())
              for (const uint32_t v : it->second)
                if (++scanned <= kMaxScanned && Within(PosD(v), px, d, len2, spatial_reach) &&
                    runs_against(v, d))
                  near(v, spatial_reach, 4 * tol);
    if (inner.empty() || seen.size() > kMaxWalk) continue;
    std::sort(inner.begin(), inner.end());
    const uint32_t c = tri_[3 * (plan.h / 3) + (plan.h % 3 + 2) % 3];
    const std::array<double, 3> n0 = AreaVector(x, y, c);
    bool ok = true;
    uint32_t from = x;
    for (size_t j = 0; ok && j <= inner.size(); ++j) {
      const uint32_t to = j < inner.size() ? uint32_t(inner[j][1]) : y;
      const std::array<double, 3> n = AreaVector(from, to, c);
      ok = EdgeUses(from, to) <= 1 && !IsZeroArea(Pos(from), Pos(to), Pos(c)) &&
           n[0] * n0[0] + n[1] * n0[1] + n[2] * n0[2] > 0 && (to == y || EdgeUses(to, c) == 0);
      from = to;
    }
    if (!ok) continue;
    for (const auto& [t, v, off] : inner) {
      plan.cut.push_back(uint32_t(v));
      plan.off.push_back(off);
    }
    plan.split = true;
  }

  // Drop the splits that would close nothing (no piece with exactly two facets) or make an edge
  // of three (an open edge left whole counts as one piece), until none is left to drop. A crack
  // may close in part: where a facet beside it is missing, its pieces there stay open, on the
  // hole's loop, which then no longer runs along the crack and back.
  absl::flat_hash_map<uint32_t, size_t> facet_plan;  // one edge per facet a call
  for (size_t i = 0; i < plans.size(); ++i)
    if (plans[i].split && !facet_plan.try_emplace(plans[i].h / 3, i).second) plans[i].split = false;
  auto pieces = [&](const Plan& p, auto&& visit) {
    uint32_t from = tri_[p.h];
    for (uint32_t v : p.cut) {
      visit(from, v);
      from = v;
    }
    visit(from, head(p.h));
  };
  bool changed = true;
  while (changed) {
    changed = false;
    absl::flat_hash_map<uint64_t, uint32_t> count;
    for (const Plan& p : plans) pieces(p, [&](uint32_t u, uint32_t v) { ++count[key(u, v)]; });
    absl::flat_hash_map<uint64_t, uint32_t> fan_edges;
    for (Plan& p : plans) {
      if (!p.split) continue;
      bool manifold = true, closes = false;
      pieces(p, [&](uint32_t u, uint32_t v) {
        const uint32_t n = count[key(u, v)];
        manifold = manifold && n <= 2;
        closes = closes || n == 2;
      });
      const uint32_t c = tri_[3 * (p.h / 3) + (p.h % 3 + 2) % 3];
      for (uint32_t v : p.cut) manifold = manifold && ++fan_edges[key(v, c)] == 1;
      if (!manifold || !closes) {
        p.split = false;
        changed = true;
      }
    }
  }

  const uint32_t nk0 = static_cast<uint32_t>(kept_.size());
  std::vector<uint32_t> after(nk0, kNoIndex);
  bool any = false;
  for (const Plan& p : plans) {
    if (!p.split) continue;
    any = true;
    const uint32_t k = p.h / 3, cy = 3 * k + (p.h % 3 + 1) % 3, cc = 3 * k + (p.h % 3 + 2) % 3;
    const uint32_t y = tri_[cy], c = tri_[cc], facet = kept_[k];
    const uint32_t ox = orig_[p.h], oy = orig_[cy], oc = orig_[cc];
    tri_[cy] = p.cut[0];  // the first piece in place: (x, m, c)
    orig_[cy] = p.cut[0];
    uint32_t prev = k;
    for (size_t j = 0; j < p.cut.size(); ++j) {
      const uint32_t m = p.cut[j], next = j + 1 < p.cut.size() ? p.cut[j + 1] : y;
      const uint32_t n = static_cast<uint32_t>(kept_.size());
      kept_.push_back(facet);
      tri_.insert(tri_.end(), {m, next, c});
      orig_.insert(orig_.end(), {m, j + 1 < p.cut.size() ? next : oy, oc});
      after.push_back(after[prev]);
      after[prev] = n;
      prev = n;
      Record(RepairKind::kSplitEdge, facet, m, PosD(m), [&] {
        return absl::StrCat("edge from vertex ", ox, " to vertex ", oy, " split at vertex ", m,
                            " (a T-junction: the facets across the crack have a vertex there",
                            p.off[j] > 0 ? absl::StrFormat(", %.3g off the edge", p.off[j]) : "",
                            ")");
      });
    }
  }
  if (any) PlaceSplitPieces(after, nk0);
  return any;
}

// Fills the holes of a surface closed but for a few missing facets, as exporters drop them. A
// component is filled only when every open loop of it is such a hole: whole (walked around the
// fans of its vertices, next_open below), at most kMaxHoleEdges edges and a fill of at most
// kMaxHoleShare of the component's area; then each loop gets the triangulation of least area that
// adds no edge the mesh has and no zero-area facet, oriented as most facets around it are, with the
// group and fields of the facet across the loop's first edge. With HoleFill::kPlanar a loop may
// also be larger where it lies in one plane and the component's loops would close it with under
// half its area: the loops of each such plane are filled together (engine/flat_openings.h), a new
// face group where the facets around them are of several. A sheet's border stays open. No point
// moves. Returns whether it added any facet (the edges are then stale).
bool Repairer::FillHoles() {
  constexpr size_t kMaxHoleEdges = 6;
  constexpr double kMaxHoleShare = 0.1;
  const HoleFill mode = options_.fill_holes;
  const uint32_t ne = static_cast<uint32_t>(ebeg_.size() - 1);
  auto head = [&](uint32_t h) { return tri_[h % 3 == 2 ? h - 2 : h + 1]; };
  absl::flat_hash_map<uint32_t, std::vector<uint32_t>> open_at;  // vertex -> its open half-edges
  for (uint32_t e = 0; e < ne; ++e)
    if (ebeg_[e + 1] - ebeg_[e] == 1) {
      const uint32_t h = ehe_[ebeg_[e]];
      open_at[tri_[h]].push_back(h);
      open_at[head(h)].push_back(h);
    }
  if (open_at.empty()) return false;

  const uint32_t nk = static_cast<uint32_t>(kept_.size());
  UnionFind components(nk);
  for (uint32_t e = 0; e < ne; ++e)
    for (uint32_t i = ebeg_[e] + 1; i < ebeg_[e + 1]; ++i)
      components.Union(ehe_[ebeg_[e]] / 3, ehe_[i] / 3);
  auto area = [&](uint32_t a, uint32_t b, uint32_t c) {
    const std::array<double, 3> n = AreaVector(a, b, c);
    return 0.5 * std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  };
  absl::flat_hash_map<uint32_t, double> component_area;  // of the components with open edges
  for (const auto& [v, hs] : open_at) component_area.try_emplace(components.Find(hs[0] / 3), 0.0);
  for (uint32_t k = 0; k < nk; ++k)
    if (auto it = component_area.find(components.Find(k)); it != component_area.end())
      it->second += area(tri_[3 * k], tri_[3 * k + 1], tri_[3 * k + 2]);

  struct Hole {
    uint32_t first;              // the open half-edge it starts with
    std::vector<uint32_t> loop;  // its vertices, in that half-edge's direction
    std::vector<uint32_t> fill;  // three vertices a facet, turned as most facets around it
    double area = 0;
    size_t loop_index = 0;  // in `loops`
  };
  std::vector<Hole> holes;
  // Every whole loop (closed, at no seam or vertex of three fans), filled or not: those of a
  // component left open are reported where they would close it with less than half its area (a
  // solid with a face missing, not a sheet's border).
  struct Loop {
    uint32_t first;
    size_t begin, size;  // its vertices in loop_vertices
    double area;         // of the plane polygon its Newell normal spans: the least a fill has
    double off_plane;    // the farthest of its vertices from that plane through their centroid
    std::array<double, 3> centre;  // of its vertices: where its report is
    bool small = false;            // a small fill of it is in `holes`
    bool flat = false;             // filled with its plane's loops (kPlanar)
    // Half its Newell normal, turned the way most facets along it run it: the loops of a surface
    // sum to the vector area of what would close it (with holes subtracted: a face's rim and its
    // holes' rims run opposite ways).
    std::array<double, 3> vector_area{};
  };
  std::vector<Loop> loops;
  std::vector<uint32_t> loop_vertices;  // one array for all: a soup may have millions of loops
  const auto describe = [&](uint32_t first, const std::vector<uint32_t>& vertices) {
    std::vector<std::array<double, 3>> p;
    std::array<double, 3> centre{};
    const size_t n = vertices.size();
    for (uint32_t v : vertices) {
      p.push_back(PosD(v));
      for (int k = 0; k < 3; ++k) centre[k] += p.back()[k] / double(n);
    }
    const std::array<double, 3> normal = NewellNormal(p.data(), n);
    const double length =
        std::sqrt(normal[0] * normal[0] + normal[1] * normal[1] + normal[2] * normal[2]);
    double off = 0;
    for (const std::array<double, 3>& a : p) {
      double d = 0;
      for (int k = 0; k < 3; ++k) d += (a[k] - centre[k]) * normal[k];
      off = std::max(off, length > 0 ? std::fabs(d) / length : HUGE_VAL);
    }
    loop_vertices.insert(loop_vertices.end(), vertices.begin(), vertices.end());
    return Loop{first,
                loop_vertices.size() - n,
                n,
                0.5 * length,
                off,
                centre,
                false,
                false,
                {0.5 * normal[0], 0.5 * normal[1], 0.5 * normal[2]}};
  };
  // The open half-edge at the other end of h's fan around v (an end of h): the next on its loop
  // where v has one fan.
  const auto fan_partner = [&](uint32_t h, uint32_t v) {
    for (uint32_t cur = h, steps = 0; steps <= nk; ++steps) {
      uint32_t other = kNoIndex;
      for (uint32_t j = cur / 3 * 3; j < cur / 3 * 3 + 3; ++j)
        if (j != cur && (tri_[j] == v || head(j) == v)) other = j;
      if (other == kNoIndex) return kNoIndex;
      const uint32_t e = edge_of_[other], uses = ebeg_[e + 1] - ebeg_[e];
      if (uses == 1) return other;
      if (uses != 2) return kNoIndex;  // a seam: no fan to follow
      cur = ehe_[ebeg_[e]] == other ? ehe_[ebeg_[e] + 1] : ehe_[ebeg_[e]];
    }
    return kNoIndex;
  };
  // The open half-edge after h on its loop, at v. Where two fans meet at v (two holes touching
  // there, as two dropped facets with a corner in common leave), the loop goes on across the gap
  // to the other fan, on its edge that runs as h's partner does (leaving v where h arrives): so
  // each hole is its own loop. Elsewhere it is h's fan partner (one fan; or more than two, where
  // the loop may pass v twice and no fill takes it).
  const auto next_open = [&](uint32_t h, uint32_t v) {
    const uint32_t partner = fan_partner(h, v);
    const std::vector<uint32_t>& at = open_at[v];
    if (partner == kNoIndex || at.size() != 4) return partner;
    uint32_t choice = kNoIndex;
    size_t matches = 0;
    for (uint32_t q : at)
      if (q != h && q != partner && (tri_[q] == v) == (tri_[partner] == v)) {
        choice = q;
        ++matches;
      }
    return matches == 1 ? choice : partner;
  };
  absl::flat_hash_map<uint32_t, bool> fillable;         // component -> every loop of it closable
  absl::flat_hash_map<uint32_t, std::string> why_open;  // component -> why not, where not plain
  absl::flat_hash_set<uint32_t> walked;                 // open half-edges already on a loop
  std::vector<uint32_t> starts;
  for (const auto& [v, hs] : open_at)
    for (uint32_t h : hs)
      if (tri_[h] == v) starts.push_back(h);
  std::sort(starts.begin(), starts.end());  // input order, whatever the map's
  for (uint32_t h0 : starts) {
    if (walked.contains(h0)) continue;
    const uint32_t comp = components.Find(h0 / 3);
    fillable.try_emplace(comp, mode != HoleFill::kNone);
    Hole hole{h0, {tri_[h0]}, {}, 0};
    bool ok = true;
    size_t along = 0;  // loop edges whose facet runs along the loop (the rest are flipped)
    for (uint32_t h = h0;;) {
      walked.insert(h);
      along += tri_[h] == hole.loop.back();
      const uint32_t v = tri_[h] == hole.loop.back() ? head(h) : tri_[h];
      const uint32_t next = next_open(h, v);
      if (next == h0) break;
      if (next == kNoIndex || walked.contains(next)) {
        ok = false;
        break;
      }
      hole.loop.push_back(v);
      h = next;
    }
    if (!ok || hole.loop.size() < 3) {
      fillable[comp] = false;
      why_open.try_emplace(comp,
                           "another of its openings passes a vertex twice or meets one "
                           "there (ambiguous: not filled)");
      continue;
    }
    loops.push_back(describe(h0, hole.loop));
    if (2 * along < hole.loop.size())
      for (double& x : loops.back().vector_area) x = -x;
    // Loops too large for a small fill may still be flat ones (kPlanar, below).
    const bool may_be_flat = mode == HoleFill::kPlanar;
    if (mode == HoleFill::kNone || hole.loop.size() > kMaxHoleEdges) {
      if (!may_be_flat) fillable[comp] = false;
      continue;
    }
    // Least-area triangulation of the loop (n <= kMaxHoleEdges).
    const size_t n = hole.loop.size();
    const auto& p = hole.loop;
    const LeastAreaFill least = LeastAreaTriangulation(
        n,
        [&](size_t i, size_t k, size_t j) {
          // A side that is not on the loop is a new edge: one the mesh has would be a third use.
          // (Side i-j is the loop's closing edge, or a side its parent checked.)
          return !((k > i + 1 && EdgeUses(p[i], p[k]) > 0) ||
                   (j > k + 1 && EdgeUses(p[k], p[j]) > 0) ||
                   IsZeroArea(Pos(p[i]), Pos(p[k]), Pos(p[j])));
        },
        [&](size_t i, size_t k, size_t j) { return area(p[i], p[k], p[j]); });
    hole.area = least.area;
    // Against the loop when most of its facets run along it (Orient turns the others).
    const bool against = 2 * along >= n;
    if (!(hole.area <= kMaxHoleShare * component_area[comp])) {
      if (!may_be_flat) fillable[comp] = false;
      continue;
    }
    for (const auto& [i, k, j] : least.triangles) {
      if (against) {
        hole.fill.insert(hole.fill.end(), {p[j], p[k], p[i]});
      } else {
        hole.fill.insert(hole.fill.end(), {p[i], p[k], p[j]});
      }
    }
    hole.loop_index = loops.size() - 1;
    loops.back().small = true;
    holes.push_back(std::move(hole));
  }

  // What a component left open would need to close: reported where that is under half its area,
  // and filled flat (kPlanar) only then.
  absl::flat_hash_map<uint32_t, double> open_area;
  for (const Loop& loop : loops) open_area[components.Find(loop.first / 3)] += loop.area;
  double plane_tolerance = -1;  // measured when first needed
  const auto tolerance = [&] {
    if (plane_tolerance < 0) plane_tolerance = ContactPlaneTolerance(in_);
    return plane_tolerance;
  };
  struct FlatFillOf {
    uint32_t comp;
    std::vector<size_t> loops;  // indices into `loops`
    FlatFill fill;
    double surface_area = 0;  // of the surfaces it joins
  };
  std::vector<FlatFillOf> flat;
  if (mode == HoleFill::kPlanar) {
    // The loops of the surfaces that a small fill alone does not close. A flat sheet (a facet
    // welded to nothing) is no solid missing a face: its loops' vector area is all of its area.
    absl::flat_hash_map<uint32_t, std::array<double, 3>> vector_open;  // per component
    for (const Loop& loop : loops)
      for (int k = 0; k < 3; ++k)
        vector_open[components.Find(loop.first / 3)][k] += loop.vector_area[k];
    const auto norm = [](const std::array<double, 3>& v) {
      return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    };
    absl::flat_hash_set<uint32_t> needs_flat;
    for (const Loop& loop : loops) {
      const uint32_t comp = components.Find(loop.first / 3);
      if (fillable[comp] && !loop.small) needs_flat.insert(comp);
    }
    for (auto it = needs_flat.begin(); it != needs_flat.end();) {
      if (norm(vector_open[*it]) < (1 - 1e-9) * component_area[*it]) {
        ++it;
        continue;
      }
      fillable[*it] = false;  // not reported either
      needs_flat.erase(it++);
    }
    std::vector<OpeningLoop> candidates;
    std::vector<size_t> candidate_loop;  // index into `loops`
    for (size_t i = 0; i < loops.size(); ++i) {
      const uint32_t comp = components.Find(loops[i].first / 3);
      if (!needs_flat.contains(comp)) continue;
      const uint32_t* v = &loop_vertices[loops[i].begin];
      candidates.push_back({std::vector<uint32_t>(v, v + loops[i].size), comp, loops[i].small});
      candidate_loop.push_back(i);
    }
    FlatFills made =
        FillFlatOpenings(in_.positions, tri_, candidates, candidates.empty() ? 0.0 : tolerance());
    for (const auto& [comp, why] : made.open) {
      fillable[comp] = false;
      why_open[comp] = why;
    }
    // The surfaces a fill joins (a face whose loss cut a piece off) are one: what would close
    // them must be under half their area, as for one surface (a sheet's border is not filled).
    UnionFind joined(nk);
    for (const FlatFill& fill : made.fills)
      for (size_t i : fill.loops)
        joined.Union(candidates[fill.loops[0]].surface, candidates[i].surface);
    absl::flat_hash_map<uint32_t, std::pair<std::array<double, 3>, double>> joined_area;
    for (uint32_t comp : needs_flat) {
      auto& [open, all] = joined_area[joined.Find(comp)];
      for (int k = 0; k < 3; ++k) open[k] += vector_open[comp][k];
      all += component_area[comp];
    }
    for (uint32_t comp : needs_flat) {
      const auto& [open, all] = joined_area[joined.Find(comp)];
      if (!(norm(open) < 0.5 * all)) fillable[comp] = false;  // not reported either
    }
    for (FlatFill& fill : made.fills) {
      const uint32_t comp = candidates[fill.loops[0]].surface;
      if (!fillable[comp]) continue;
      FlatFillOf of{comp, {}, std::move(fill), 0.0};
      absl::flat_hash_set<uint32_t> surfaces;  // those the fill joins
      for (size_t i : of.fill.loops) {
        of.loops.push_back(candidate_loop[i]);
        loops[candidate_loop[i]].flat = true;
        if (surfaces.insert(candidates[i].surface).second)
          of.surface_area += component_area[candidates[i].surface];
      }
      flat.push_back(std::move(of));
    }
  }

  for (const Loop& loop : loops) {
    const uint32_t comp = components.Find(loop.first / 3);
    if (fillable[comp] || !(open_area[comp] < 0.5 * component_area[comp])) continue;
    const bool planar = loop.size > 3 && loop.off_plane <= tolerance();
    const bool small =
        loop.size <= kMaxHoleEdges && loop.area <= kMaxHoleShare * component_area[comp];
    const uint32_t* vertices = &loop_vertices[loop.begin];
    const auto why = [&]() -> std::string {
      if (mode == HoleFill::kNone) return "hole filling is off (fill_holes none)";
      if (mode == HoleFill::kPlanar || small)
        if (auto it = why_open.find(comp); it != why_open.end()) return it->second;
      if (small) return "another loop of its surface is too large to fill";
      return absl::StrCat(
          "larger than a few missing facets: the surface is not closed (tetgen and solid FE "
          "models need it closed)",
          planar && mode == HoleFill::kSmall ? "; --fill-holes planar fills a flat one" : "");
    };
    Record(RepairKind::kHoleLeft, kept_[loop.first / 3], vertices[0], loop.centre, [&] {
      return absl::StrFormat(
          "a loop of %u open edges (from vertex %u) left open: a fill would take at least %.3g "
          "(%.2g%% of its surface's area), %s; %s",
          loop.size, vertices[0], loop.area, 100 * loop.area / component_area[comp],
          planar          ? "in one plane (a flat face missing?)"
          : loop.size > 3 ? "not in one plane"
                          : "a triangle",
          why());
    });
  }
  bool any = false;
  for (const Hole& hole : holes) {
    const uint32_t comp = components.Find(hole.first / 3);
    if (!fillable[comp] || loops[hole.loop_index].flat) continue;
    any = true;
    const uint32_t facet = kept_[hole.first / 3];
    for (size_t c = 0; c < hole.fill.size(); c += 3) {
      kept_.push_back(facet);
      tri_.insert(tri_.end(), &hole.fill[c], &hole.fill[c] + 3);
      orig_.insert(orig_.end(), &hole.fill[c], &hole.fill[c] + 3);
    }
    std::array<double, 3> at{};
    for (uint32_t v : hole.loop)
      for (int k = 0; k < 3; ++k) at[k] += PosD(v)[k] / double(hole.loop.size());
    Record(RepairKind::kFilledHole, facet, hole.loop[0], at, [&] {
      return absl::StrFormat(
          "a hole of %u edges (vertices %s) closed by %u facet%s of area %.3g (%.2g%% of its "
          "surface's), with facet %u's group and fields",
          hole.loop.size(), absl::StrJoin(hole.loop, ", "), hole.fill.size() / 3,
          hole.fill.size() == 3 ? "" : "s", hole.area, 100 * hole.area / component_area[comp],
          facet);
    });
  }
  for (const FlatFillOf& of : flat) {
    any = true;
    const Loop& first = loops[of.loops[0]];
    const uint32_t facet = kept_[first.first / 3];
    // Its own face group where the facets around it are of several (a CAD face of its own).
    std::optional<uint32_t> group;
    if (!in_.face_groups.empty()) {
      absl::flat_hash_set<uint32_t> around;
      for (uint32_t k : of.fill.rim_facets) around.insert(in_.face_groups[kept_[k]]);
      if (around.size() > 1) {
        if (next_group_ == 0)
          next_group_ = *std::max_element(in_.face_groups.begin(), in_.face_groups.end()) + 1;
        group = next_group_++;
      }
    }
    const size_t notch_facets = of.fill.notch_origins.size(),
                 flat_facets = of.fill.facets.size() / 3 - notch_facets;
    for (size_t c = 0; c < of.fill.facets.size(); c += 3) {
      if (c / 3 >= flat_facets) {  // a notch's: a facet of the face beside it
        kept_.push_back(kept_[of.fill.notch_origins[c / 3 - flat_facets]]);
      } else {
        if (group) own_group_[static_cast<uint32_t>(kept_.size())] = *group;
        kept_.push_back(facet);
      }
      tri_.insert(tri_.end(), &of.fill.facets[c], &of.fill.facets[c] + 3);
      orig_.insert(orig_.end(), &of.fill.facets[c], &of.fill.facets[c] + 3);
    }
    size_t corners = 0;
    std::array<double, 3> at{};
    for (size_t i : of.loops) corners += loops[i].size;
    for (size_t i : of.loops)
      for (int k = 0; k < 3; ++k)
        at[k] += loops[i].centre[k] * double(loops[i].size) / double(corners);
    Record(RepairKind::kFilledHole, facet, loop_vertices[first.begin], at, [&] {
      return absl::StrFormat(
          "an opening in one plane (%u edges in %u loop%s, from vertex %u) closed by %u facets%s "
          "of area %.3g (%.2g%% of its surface's), %s; %s",
          of.fill.loop_edges, of.loops.size(), of.loops.size() == 1 ? "" : "s",
          loop_vertices[first.begin], of.fill.facets.size() / 3,
          notch_facets == 0
              ? ""
              : absl::StrCat(" (", notch_facets, " of them closing notches off its plane)"),
          of.fill.area, 100 * of.fill.area / of.surface_area,
          group ? absl::StrCat("as new face group ", *group, ", with facet ", facet, "'s fields")
                : absl::StrCat("with facet ", facet, "'s group and fields"),
          of.fill.flush_edges == of.fill.rim_edges
              ? "flush with the facets around it: a hole through a flat face, closed (was it "
                "meant to be open?)"
          : of.fill.flush_edges == 0 ? "at an edge of the surface all round: a flat face missing"
                                     : "a flat face missing, or part of one");
    });
  }
  return any;
}

// Components are connected through manifold edges (2 facets). In each, a breadth-first walk
// gives every facet its parity relative to the first; the component then takes the orientation
// of the majority of its facets, or, when it is closed (kOn), the one that makes the mesh bound a
// volume: outward, and inward where it lies inside an odd number of other closed components (a
// cavity's wall faces into the cavity; CGAL's orient_to_bound_a_volume rule).
void Repairer::Orient() {
  const uint32_t nk = static_cast<uint32_t>(kept_.size());
  std::vector<uint32_t> comp(nk, kNoIndex), order;
  std::vector<uint8_t> parity(nk, 0), flip(nk, 0);
  order.reserve(nk);
  // Each consistent component: its facets order[begin, end), seed orientation kept or not.
  struct Component {
    uint32_t seed, begin, end;
    bool keep_seed, closed;
    double volume = 0;  // signed, with the seed's orientation (closed components)
    std::array<double, 3> lo{}, hi{};
  };
  std::vector<Component> components;
  for (uint32_t seed = 0; seed < nk; ++seed) {
    if (comp[seed] != kNoIndex) continue;
    const uint32_t begin = static_cast<uint32_t>(order.size());
    order.push_back(seed);
    comp[seed] = seed;
    bool closed = true, conflict = false;
    for (size_t qi = begin; qi < order.size(); ++qi) {
      const uint32_t x = order[qi];
      for (uint32_t i = 0; i < 3; ++i) {
        const uint32_t h = 3 * x + i, e = edge_of_[h];
        if (ebeg_[e + 1] - ebeg_[e] != 2) {
          closed = false;
          continue;
        }
        const uint32_t g = ehe_[ebeg_[e]] == h ? ehe_[ebeg_[e] + 1] : ehe_[ebeg_[e]];
        const uint32_t y = g / 3;
        const bool same_direction = tri_[h] == tri_[g];  // both start at the same vertex
        const uint8_t want = parity[x] ^ uint8_t(same_direction);
        if (comp[y] == kNoIndex) {
          comp[y] = seed;
          parity[y] = want;
          order.push_back(y);
        } else if (parity[y] != want) {
          conflict = true;
        }
      }
    }
    const uint32_t end = static_cast<uint32_t>(order.size());
    if (conflict) {  // a Moebius band or worse: no flip makes it consistent
      Record(RepairKind::kNonOrientable, kept_[seed], -1, Centroid(&tri_[3 * seed]),
             absl::StrCat("component of ", end - begin,
                          " facets: no orientation is consistent; left as it was"));
      continue;
    }
    size_t odd = 0;
    for (uint32_t i = begin; i < end; ++i) odd += parity[order[i]];
    Component c{seed, begin, end, 2 * odd <= end - begin, closed};  // a tie keeps the first
    if (closed && !strict_ && options_.orient_outward) {
      // Signed volume with the seed's orientation, about the seed's first corner.
      const std::array<double, 3> o = PosD(tri_[3 * seed]);
      c.lo = c.hi = o;
      for (uint32_t i = begin; i < end; ++i) {
        const uint32_t x = order[i];
        std::array<double, 3> p[3];
        for (int j = 0; j < 3; ++j) {
          p[j] = PosD(tri_[3 * x + j]);
          for (int k = 0; k < 3; ++k) {
            c.lo[k] = std::min(c.lo[k], p[j][k]);
            c.hi[k] = std::max(c.hi[k], p[j][k]);
            p[j][k] -= o[k];
          }
        }
        const double det = p[0][0] * (p[1][1] * p[2][2] - p[1][2] * p[2][1]) -
                           p[0][1] * (p[1][0] * p[2][2] - p[1][2] * p[2][0]) +
                           p[0][2] * (p[1][0] * p[2][1] - p[1][1] * p[2][0]);
        c.volume += parity[x] ? -det : det;
      }
    }
    components.push_back(c);
  }
  // Whether a closed component lies inside another whose box holds its box: the other's winding
  // number about the centroids of a few of its facets, spread over it, is ±1 at each. Parts that
  // cross each other (an assembly exported overlapping) are in at some and out at others: not
  // inside. Each enclosing candidate's test is built once, when first asked.
  absl::flat_hash_map<const Component*, std::unique_ptr<PointInShell>> inside_tests;
  const auto encloses = [&](const Component& outer, const Component& inner) {
    std::unique_ptr<PointInShell>& test = inside_tests[&outer];
    if (!test) {
      std::vector<uint32_t> corners;
      corners.reserve(3 * size_t(outer.end - outer.begin));
      for (uint32_t i = outer.begin; i < outer.end; ++i) {
        const uint32_t* t = &tri_[3 * order[i]];
        corners.insert(corners.end(),
                       {t[0], parity[order[i]] ? t[2] : t[1], parity[order[i]] ? t[1] : t[2]});
      }
      test = std::make_unique<PointInShell>(in_.positions.data(), std::move(corners));
    }
    constexpr uint32_t kSamples = 8;
    const uint32_t n = inner.end - inner.begin, samples = std::min(n, kSamples);
    for (uint32_t s = 0; s < samples; ++s) {
      const std::array<double, 3> at =
          Centroid(&tri_[3 * order[inner.begin + uint64_t(s) * n / samples]]);
      if (test->Winding({at[0], at[1], at[2]}) == 0) return false;
    }
    return true;
  };
  std::vector<uint32_t> shells;  // closed components with a volume
  std::vector<AxisBox> boxes;
  if (!strict_ && options_.orient_outward)
    for (uint32_t i = 0; i < components.size(); ++i)
      if (components[i].closed && components[i].volume != 0) {
        shells.push_back(i);
        boxes.push_back({components[i].lo, components[i].hi});
      }
  const std::vector<std::vector<uint32_t>> candidates = ContainingBoxes(boxes);
  // A shell's enclosers before it: each box that holds an encloser's box holds its own too.
  std::vector<uint32_t> by_nesting(shells.size());
  std::iota(by_nesting.begin(), by_nesting.end(), 0u);
  std::stable_sort(by_nesting.begin(), by_nesting.end(), [&](uint32_t a, uint32_t b) {
    return candidates[a].size() < candidates[b].size();
  });
  // Per shell: a surface two bodies share, which bounds a body on both sides: it counts twice
  // in the depth of what lies inside it (a cavity in an insert faces into the cavity, a third
  // layer's surface into that layer).
  std::vector<uint8_t> shared_wall(shells.size(), 0);
  std::vector<uint8_t> taken_from_twin(nk, 0);
  for (const uint32_t s : by_nesting) {
    Component& c = components[shells[s]];
    size_t depth = 0;
    for (uint32_t other : candidates[s])
      if (encloses(components[shells[other]], c)) depth += shared_wall[other] ? 2 : 1;
    const bool outward = depth % 2 == 0;
    const bool keep_seed = (c.volume > 0) == outward;
    bool shared = !outward && !twin_.empty();
    for (uint32_t i = c.begin; i < c.end && shared; ++i)
      shared = twin_[kept_[order[i]]] != kNoIndex;
    shared_wall[s] = shared;
    if (shared) {
      // Its facets face as the outer body's copies did: no facet was turned, the other copy kept.
      for (uint32_t i = c.begin; i < c.end; ++i) taken_from_twin[order[i]] = 1;
      KeepSharedShell(c.seed, order, c.begin, c.end, parity, keep_seed);
      Record(RepairKind::kSharedShellLeft, kept_[c.seed], -1, Centroid(&tri_[3 * c.seed]),
             absl::StrFormat(
                 "closed surface of %u facets inside another body, every facet of it written "
                 "twice, facing both ways: the surface two bodies share (a body inside "
                 "another: an insert, a core, a part under a coating), or a cavity's wall "
                 "written twice; kept once, as the wall of a cavity: the body inside it "
                 "(volume %.6g) is not in the volume, the moments or the mass budgets",
                 c.end - c.begin, std::fabs(c.volume) / 6.0));
    } else if (keep_seed != c.keep_seed) {
      const uint32_t n = c.end - c.begin;
      size_t flipped = 0;
      for (uint32_t i = c.begin; i < c.end; ++i) flipped += parity[order[i]] == uint8_t(keep_seed);
      Record(RepairKind::kReversedComponent, kept_[c.seed], -1, Centroid(&tri_[3 * c.seed]),
             outward ? absl::StrCat("closed component of ", n, " facets had a negative volume; ",
                                    flipped, " facets flipped")
                     : absl::StrCat("closed component of ", n,
                                    " facets lies inside another (the wall of a cavity) but "
                                    "faced outward; ",
                                    flipped, " facets flipped to face into the cavity"));
    }
    c.keep_seed = keep_seed;
  }
  for (const Component& c : components)
    for (uint32_t i = c.begin; i < c.end; ++i)
      flip[order[i]] = parity[order[i]] == uint8_t(c.keep_seed);
  for (uint32_t k = 0; k < nk; ++k) {
    if (!flip[k]) continue;
    if (!taken_from_twin[k])
      Record(RepairKind::kFlippedFacet, kept_[k], -1, Centroid(&tri_[3 * k]),
             strict_ ? "oriented against its neighbours" : "orientation reversed");
    std::swap(tri_[3 * k + 1], tri_[3 * k + 2]);
    std::swap(orig_[3 * k + 1], orig_[3 * k + 2]);
  }
}

bool Repairer::DropLoosePieces() {
  const std::vector<uint32_t> uses = EdgeUseCounts();
  // A closed mesh, the common case, has no piece to look for.
  if (std::find(uses.begin(), uses.end(), 1u) == uses.end()) return false;
  const std::vector<LoosePiece> pieces =
      FindLoosePieces(in_.positions.data(), tri_, edge_of_, uses, options_.loose_piece_share);
  if (pieces.empty()) return false;
  const uint32_t nk = static_cast<uint32_t>(kept_.size());
  std::vector<uint8_t> drop(nk, 0);
  for (const LoosePiece& piece : pieces) {
    for (uint32_t k : piece.faces) drop[k] = 1;
    Record(RepairKind::kLoosePiece, kept_[piece.faces[0]], -1, piece.centre, [&] {
      return absl::StrFormat(
          "%u facet%s of area %.3g (%.2g%% of the bodies' area), open and %s: removed "
          "(%s; --loose-piece-share 0 keeps it)",
          piece.faces.size(), piece.faces.size() == 1 ? "" : "s", piece.area,
          100 * piece.area / piece.body_area,
          piece.attached_edges == 0 ? std::string("joined to nothing")
                                    : absl::StrCat("hanging from ", piece.attached_edges, " edge",
                                                   piece.attached_edges == 1 ? "" : "s",
                                                   " of a body, which it made non-manifold"),
          piece.attached_edges == 0 ? "a stray facet or a leftover face" : "a dangling facet");
    });
  }
  RemoveFacets(drop);
  return true;
}

// The kept copy of a surface two bodies share (facets order[begin, end) of a component) faces as
// the orientation leaves it, into the inner body: where that is its removed twin's way, it takes
// the twin's group and fields, so that each body's facets keep theirs. Listed for PrepareMesh.
void Repairer::KeepSharedShell(uint32_t seed, const std::vector<uint32_t>& order, uint32_t begin,
                               uint32_t end, const std::vector<uint8_t>& parity, bool keep_seed) {
  RepairResult::SharedShell shell{seed, {}};
  for (uint32_t i = begin; i < end; ++i) {
    const uint32_t k = order[i];
    const bool turned = parity[k] == uint8_t(keep_seed);
    if (turned) data_from_[k] = twin_[kept_[k]];
    if (in_.face_groups.empty()) continue;
    const uint32_t own = in_.face_groups[kept_[k]], twin = in_.face_groups[twin_[kept_[k]]];
    const uint32_t now = turned ? twin : own, other = turned ? own : twin;
    if (absl::c_none_of(shell.twin_groups, [&](const auto& g) { return g.first == now; }))
      shell.twin_groups.push_back({now, other});
  }
  result_.shared_shells.push_back(std::move(shell));
}

void Repairer::RemoveFacets(const std::vector<uint8_t>& drop) {
  const uint32_t nk = static_cast<uint32_t>(kept_.size());
  absl::flat_hash_map<uint32_t, uint32_t> own_group, data_from;
  uint32_t kept = 0;
  for (uint32_t k = 0; k < nk; ++k) {
    if (drop[k]) continue;
    if (const auto own = own_group_.find(k); own != own_group_.end()) own_group[kept] = own->second;
    if (const auto from = data_from_.find(k); from != data_from_.end())
      data_from[kept] = from->second;
    kept_[kept] = kept_[k];
    for (int i = 0; i < 3; ++i) {
      tri_[3 * kept + i] = tri_[3 * k + i];
      orig_[3 * kept + i] = orig_[3 * k + i];
    }
    ++kept;
  }
  kept_.resize(kept);
  tri_.resize(3 * size_t(kept));
  orig_.resize(3 * size_t(kept));
  own_group_ = std::move(own_group);
  data_from_ = std::move(data_from);
}

bool Repairer::DropDuplicateBodies() {
  const std::vector<DuplicateBody> copies = FindDuplicateBodies(
      in_.positions.data(), tri_, edge_of_, EdgeUseCounts(), options_.duplicate_body_offset);
  if (copies.empty()) return false;
  std::vector<uint8_t> drop(kept_.size(), 0);
  for (const DuplicateBody& copy : copies) {
    for (uint32_t k : copy.faces) drop[k] = 1;
    Record(RepairKind::kDuplicateBody, kept_[copy.faces[0]], -1, copy.centre, [&] {
      return absl::StrFormat(
          "closed body of %u facets (volume %.6g) repeats the body of %u facets at facet %u: "
          "each lies within %.3g of the other (%.2g of its mean thickness 2V/A = %.3g); "
          "removed, the first kept (--duplicate-body-offset 0 keeps both)",
          copy.faces.size(), copy.volume, copy.kept_faces, kept_[copy.kept_face], copy.distance,
          copy.distance / copy.thickness, copy.thickness);
    });
  }
  // The copy's vertices go with it: its record stands for them (no weld or unreferenced record).
  went_with_copy_.resize(nv_, 0);
  for (uint32_t k = 0; k < drop.size(); ++k)
    if (drop[k])
      for (int i = 0; i < 3; ++i) went_with_copy_[orig_[3 * k + i]] = 1;
  RemoveFacets(drop);
  return true;
}

// Each round finds every fold and flips those whose flip unfolds them, one per facet (a flip
// changes its facets' other edges), so a fan turned over may take several rounds.
void Repairer::UnfoldEdges() {
  constexpr int kMaxRounds = 8;
  const double plane_tolerance = ContactPlaneTolerance(in_);
  const auto at = [&](uint32_t w) {
    const std::array<double, 3> p = PosD(Origin(w));
    return DVec3{p[0], p[1], p[2]};
  };
  struct Fold {
    uint32_t k0, k1;  // kept facets (a, b, c) and (b, a, d)
    uint32_t ja, jc;  // corners of k0: a (then b) and c
    uint32_t jd;      // corner of k1: d (then b, a)
  };
  const auto find_folds = [&] {
    // Facets of a fold face opposite ways: comparing the normals first passes over nearly
    // every edge of a part cheaply.
    std::vector<DVec3> normal(kept_.size());
    for (size_t k = 0; k < kept_.size(); ++k) {
      const DVec3 p = at(tri_[3 * k]);
      normal[k] = Cross(at(tri_[3 * k + 1]) - p, at(tri_[3 * k + 2]) - p);
    }
    std::vector<Fold> folds;
    for (size_t e = 0; e + 1 < ebeg_.size(); ++e) {
      if (ebeg_[e + 1] - ebeg_[e] != 2) continue;
      const uint32_t k0 = ehe_[ebeg_[e]] / 3, k1 = ehe_[ebeg_[e] + 1] / 3;
      if (k0 == k1 || Dot(normal[k0], normal[k1]) >= 0.0) continue;
      // Oriented alike: k1 runs b -> a (a component left non-orientable may not).
      const std::optional<std::pair<int, int>> apexes =
          OppositeApexes(&tri_[3 * k0], &tri_[3 * k1]);
      if (!apexes) continue;
      const uint32_t jc = apexes->first, jd = apexes->second, ja = (jc + 1) % 3;
      const uint32_t a = tri_[3 * k0 + ja], b = tri_[3 * k0 + (jc + 2) % 3];
      if (IsFold(at(a), at(b), at(tri_[3 * k0 + jc]), at(tri_[3 * k1 + jd]), plane_tolerance))
        folds.push_back({k0, k1, ja, jc, jd});
    }
    return folds;
  };
  const auto same_attributes = [&](uint32_t k0, uint32_t k1) {
    const uint32_t f0 = kept_[k0], f1 = kept_[k1];
    if (!in_.face_groups.empty() && in_.face_groups[f0] != in_.face_groups[f1]) return false;
    for (const FaceField& field : in_.face_fields)
      if (std::memcmp(&field.values[f0], &field.values[f1], sizeof(float)) != 0) return false;
    return true;
  };
  const auto record = [&](RepairKind kind, const Fold& f, std::string why) {
    const uint32_t a = tri_[3 * f.k0 + f.ja];
    const uint32_t b = tri_[3 * f.k0 + (f.ja + 1) % 3];
    const std::array<double, 3> pb = PosD(Origin(b));
    const uint32_t f0 = std::min(kept_[f.k0], kept_[f.k1]), f1 = std::max(kept_[f.k0], kept_[f.k1]);
    Record(kind, f0, orig_[3 * f.k0 + f.ja], PosD(Origin(a)), [&] {
      // Split pieces and hole fills carry the input facet they came from.
      const std::string facets = f0 == f1
                                     ? absl::StrCat("two facets made from facet ", f0,
                                                    " (pieces of it, or a hole's fill beside it)")
                                     : absl::StrCat("facets ", f0, " and ", f1);
      return absl::StrCat("to ", Point(World(pb)), ": ", facets,
                          " lie on each other in their plane, one turned over", why);
    });
  };
  for (int round = 0;; ++round) {
    const std::vector<Fold> folds = find_folds();
    if (folds.empty()) break;
    if (strict_) {
      for (const Fold& f : folds) record(RepairKind::kUnfoldedEdge, f, "");
      break;
    }
    std::vector<uint8_t> touched(kept_.size(), 0);
    absl::flat_hash_set<uint64_t> made;  // edges this round's flips made
    std::vector<std::pair<const Fold*, const char*>> left;
    for (const Fold& f : folds) {
      const uint32_t a = tri_[3 * f.k0 + f.ja], b = tri_[3 * f.k0 + (f.ja + 1) % 3];
      const uint32_t c = tri_[3 * f.k0 + f.jc], d = tri_[3 * f.k1 + f.jd];
      const uint64_t cd = uint64_t{std::min(c, d)} << 32 | std::max(c, d);
      const char* why = nullptr;
      if (touched[f.k0] || touched[f.k1]) {
        why = "";  // a neighbour flipped this round: the next round decides
      } else if (!same_attributes(f.k0, f.k1)) {
        why = "; they belong to different face groups or carry different field values";
      } else if (c == d || EdgeUses(c, d) != 0 || made.contains(cd)) {
        why = "; the other diagonal is an edge already";
      } else if (!FlipUnfolds(at(a), at(b), at(c), at(d))) {
        why = "; the other diagonal would turn a facet over";
      }
      if (why != nullptr) {
        left.emplace_back(&f, why);
        continue;
      }
      record(RepairKind::kUnfoldedEdge, f,
             absl::StrCat(": edge replaced by the other diagonal, ", Point(World(PosD(Origin(c)))),
                          " to ", Point(World(PosD(Origin(d))))));
      const uint32_t oa = orig_[3 * f.k0 + f.ja], ob = orig_[3 * f.k0 + (f.ja + 1) % 3],
                     oc = orig_[3 * f.k0 + f.jc], od = orig_[3 * f.k1 + f.jd];
      const uint32_t k0 = 3 * f.k0, k1 = 3 * f.k1;
      tri_[k0] = a, tri_[k0 + 1] = d, tri_[k0 + 2] = c;
      orig_[k0] = oa, orig_[k0 + 1] = od, orig_[k0 + 2] = oc;
      tri_[k1] = b, tri_[k1 + 1] = c, tri_[k1 + 2] = d;
      orig_[k1] = ob, orig_[k1 + 1] = oc, orig_[k1 + 2] = od;
      touched[f.k0] = touched[f.k1] = 1;
      made.insert(cd);
    }
    const bool flipped = left.size() < folds.size();
    if (!flipped || round + 1 == kMaxRounds) {
      if (flipped) {  // the last round's flips may have made or left folds: look once more
        BuildEdges();
        for (const Fold& f : find_folds())
          record(RepairKind::kFoldLeft, f,
                 absl::StrCat("; unfolding stopped after ", kMaxRounds, " rounds of flips"));
      } else {
        for (const auto& [f, why] : left) record(RepairKind::kFoldLeft, *f, why);
      }
      break;
    }
    BuildEdges();
  }
}

// Corners at one vertex belong to the same fan when their facets share an edge at that vertex
// (a manifold edge or a seam: seam vertices are shared by the parts and stay one vertex). A
// vertex with several fans gets one vertex per fan. Where the weld made the vertex and each fan
// used its own input vertex, the fans get those back: the weld is undone, not reported.
void Repairer::SplitVertices() {
  const uint32_t nc = static_cast<uint32_t>(tri_.size());
  UnionFind corners(nc);
  for (size_t e = 0; e + 1 < ebeg_.size(); ++e) {
    const uint32_t k0 = ehe_[ebeg_[e]] / 3;
    for (uint32_t i = ebeg_[e] + 1; i < ebeg_[e + 1]; ++i) {
      const uint32_t k = ehe_[i] / 3;
      for (uint32_t j = 0; j < 3; ++j) {  // the two shared vertices are the edge's ends
        const uint32_t c = CornerAt(k, tri_[3 * k0 + j]);
        if (tri_[c] == tri_[3 * k0 + j]) corners.Union(3 * k0 + j, c);
      }
    }
  }
  std::vector<uint32_t> first_root(nv_, kNoIndex);
  std::vector<uint8_t> non_manifold(nv_, 0);
  for (uint32_t c = 0; c < nc; ++c) {
    const uint32_t v = tri_[c], r = corners.Find(c);
    if (first_root[v] == kNoIndex) {
      first_root[v] = r;
    } else if (r != first_root[v]) {
      non_manifold[v] = 1;
    }
  }
  std::vector<std::pair<uint32_t, uint32_t>> at_split;  // (vertex, corner) at non-manifold ones
  for (uint32_t c = 0; c < nc; ++c)
    if (non_manifold[tri_[c]]) at_split.push_back({tri_[c], c});
  std::sort(at_split.begin(), at_split.end());
  struct Fan {
    uint32_t root, orig, first_corner, vertex;
  };
  std::vector<Fan> fans;
  for (size_t begin = 0, end; begin < at_split.size(); begin = end) {
    const uint32_t v = at_split[begin].first;
    fans.clear();
    for (end = begin; end < at_split.size() && at_split[end].first == v; ++end) {
      const uint32_t c = at_split[end].second, r = corners.Find(c);
      auto it = std::find_if(fans.begin(), fans.end(), [r](const Fan& f) { return f.root == r; });
      if (it == fans.end()) {
        fans.push_back({r, orig_[c], c, kNoIndex});
      } else if (it->orig != orig_[c]) {
        it->orig = kNoIndex;  // the fan mixes input vertices
      }
    }
    auto taken = [&](uint32_t w) {
      return std::any_of(fans.begin(), fans.end(), [w](const Fan& f) { return f.vertex == w; });
    };
    for (Fan& fan : fans)
      if (fan.orig != kNoIndex && !taken(fan.orig)) fan.vertex = fan.orig;
    size_t copies = 0;
    for (Fan& fan : fans) {
      if (fan.vertex != kNoIndex) continue;
      if (!taken(v)) {
        fan.vertex = v;
        continue;
      }
      fan.vertex = static_cast<uint32_t>(nv_ + copy_of_.size());
      copy_of_.push_back(v);
      ++copies;
    }
    if (copies > 0)
      Record(RepairKind::kSplitVertex, first_facet_[v], v, PosD(v), [&] {
        std::string facets;
        for (size_t j = 0; j < fans.size(); ++j)
          absl::StrAppend(&facets, j == 0 ? "" : ", ", kept_[fans[j].first_corner / 3]);
        return absl::StrCat(fans.size(), " fans meet there (first facets ", facets, ")",
                            strict_ ? "" : absl::StrCat("; ", copies, " copies added"));
      });
    for (size_t j = begin; j < end; ++j) {
      const uint32_t c = at_split[j].second, r = corners.Find(c);
      for (const Fan& fan : fans)
        if (fan.root == r) tri_[c] = fan.vertex;
    }
  }
}

// Welded and dropped vertices, judged from where each input vertex's surviving corners went.
void Repairer::ReportVertices() {
  std::vector<uint32_t> went(nv_, kNoIndex);  // an input vertex's output vertex (origin id)
  std::vector<uint8_t> moved(nv_, 0);
  for (size_t c = 0; c < tri_.size(); ++c) {
    const uint32_t o = orig_[c];
    const uint32_t origin = Origin(tri_[c]);
    if (origin != o && !moved[o]) {
      moved[o] = 1;
      went[o] = origin;
    }
    if (went[o] == kNoIndex) went[o] = origin;
  }
  for (uint32_t o = 0; o < nv_; ++o) {
    if (went[o] == kNoIndex && !went_with_copy_.empty() && went_with_copy_[o]) continue;
    if (went[o] == kNoIndex && rep_[o] != o) {  // all its facets were removed after the weld
      moved[o] = 1;
      went[o] = rep_[o];
    }
    if (moved[o]) {
      Record(RepairKind::kWeldedVertex, first_facet_[o], o, PosD(o), [&] {
        const uint32_t r = went[o];
        double d2 = 0;
        for (int k = 0; k < 3; ++k)
          d2 += (double(Pos(o)[k]) - Pos(r)[k]) * (double(Pos(o)[k]) - Pos(r)[k]);
        return absl::StrFormat("merged into vertex %u (distance %.3g)", r, std::sqrt(d2));
      });
    } else if (went[o] == kNoIndex) {
      Record(RepairKind::kUnreferencedVertex, -1, o, PosD(o), [&] {
        return first_facet_[o] == kNoIndex
                   ? std::string("no facet uses it")
                   : absl::StrCat("its facets were removed (first: ", first_facet_[o], ")");
      });
    }
  }
}

// Stitched edges (two facets now share an edge that their input vertices did not) and seams.
// Runs after the split: the facets on an edge are in one fan at each end, so share its copies.
void Repairer::ReportEdges() {
  for (size_t e = 0; e + 1 < ebeg_.size(); ++e) {
    const uint32_t n = ebeg_[e + 1] - ebeg_[e];
    if (n == 1 || (n == 2 && strict_)) continue;
    const uint32_t k0 = ehe_[ebeg_[e]] / 3, k1 = ehe_[ebeg_[e] + 1] / 3;
    uint32_t ends[2], m = 0;  // corners of k0 on the edge
    for (uint32_t j = 0; j < 3 && m < 2; ++j)
      if (tri_[CornerAt(k1, tri_[3 * k0 + j])] == tri_[3 * k0 + j]) ends[m++] = 3 * k0 + j;
    if (n == 2 && orig_[CornerAt(k1, tri_[ends[0]])] == orig_[ends[0]] &&
        orig_[CornerAt(k1, tri_[ends[1]])] == orig_[ends[1]])
      continue;
    const std::array<double, 3> a = PosD(Origin(tri_[ends[0]])), b = PosD(Origin(tri_[ends[1]]));
    if (n == 2) {
      Record(RepairKind::kStitchedEdge, kept_[k0], orig_[ends[0]], a, [&] {
        return absl::StrCat("to ", Point(World(b)), ": joins facets ", kept_[k0], " and ",
                            kept_[k1]);
      });
      continue;
    }
    SeamEdge seam;
    seam.a = tri_[ends[0]];
    seam.b = tri_[ends[1]];
    for (uint32_t i = ebeg_[e]; i < ebeg_[e + 1]; ++i) seam.facets.push_back(kept_[ehe_[i] / 3]);
    std::sort(seam.facets.begin(), seam.facets.end());
    Record(RepairKind::kSeamEdge, seam.facets[0], orig_[ends[0]], a,
           [&] { return SeamDetail(World(b), n, seam.facets); });
    for (int k = 0; k < 3; ++k) {
      seam.pa[k] = float(a[k]);
      seam.pb[k] = float(b[k]);
    }
    result_.seams.push_back(std::move(seam));
  }
}

void Repairer::WriteOutput(RawMesh& mesh) {
  // Output vertices: used input vertices in order, then the split copies.
  const size_t nw = nv_ + copy_of_.size();
  std::vector<uint32_t> out(nw, kNoIndex);
  for (uint32_t w : tri_) out[w] = 0;
  uint32_t next = 0;
  RawMesh r;
  r.origin = in_.origin;
  for (size_t w = 0; w < nw; ++w) {
    if (out[w] == kNoIndex) continue;
    out[w] = next++;
    const uint32_t from = w < nv_ ? uint32_t(w) : copy_of_[w - nv_];
    r.positions.insert(r.positions.end(), Pos(from), Pos(from) + 3);
    result_.vertex_origin.push_back(from);
  }
  r.triangles.resize(tri_.size());
  for (size_t c = 0; c < tri_.size(); ++c) r.triangles[c] = out[tri_[c]];
  if (!in_.face_groups.empty())
    for (uint32_t k = 0; k < kept_.size(); ++k) {
      const auto own = own_group_.find(k);
      r.face_groups.push_back(own != own_group_.end() ? own->second
                                                      : in_.face_groups[DataSource(k)]);
    }
  for (const FaceField& field : in_.face_fields) {
    r.face_fields.push_back({field.name, {}});
    r.face_fields.back().values.reserve(kept_.size());
    for (uint32_t k = 0; k < kept_.size(); ++k)
      r.face_fields.back().values.push_back(field.values[DataSource(k)]);
  }
  for (SeamEdge& seam : result_.seams) {
    seam.a = out[seam.a];
    seam.b = out[seam.b];
  }
  result_.facet_origin = kept_;
  mesh = std::move(r);
}

absl::Status Repairer::StrictError() const {
  const RepairReport& report = result_.report;
  std::vector<std::string> parts;
  size_t total = 0;
  for (size_t k = 0; k < kNumRepairKinds; ++k)
    if (report.counts[k] > 0) {
      total += report.counts[k];
      parts.push_back(absl::StrCat(report.counts[k], " ",
                                   report.counts[k] == 1 ? kKinds[k].singular : kKinds[k].plural));
    }
  std::string message =
      absl::StrCat("repair is off and the mesh has ", total, " defect", total == 1 ? "" : "s", " (",
                   absl::StrJoin(parts, ", "), "): ");
  std::string details;
  for (size_t k = 0; k < kNumRepairKinds; ++k) {
    size_t listed = 0;
    for (const RepairRecord& record : report.records)
      if (static_cast<size_t>(record.kind) == k) {
        absl::StrAppend(&details, details.empty() ? "" : "; ", record.ToString());
        ++listed;
      }
    if (report.counts[k] > listed)
      absl::StrAppend(&details, "; and ", report.counts[k] - listed, " more ", kKinds[k].plural);
  }
  return absl::InvalidArgumentError(message + details);
}

void Repairer::ReferencedBox(double lo[3], double hi[3]) const {
  for (int k = 0; k < 3; ++k) {
    lo[k] = HUGE_VAL;
    hi[k] = -HUGE_VAL;
  }
  for (uint32_t v = 0; v < nv_; ++v) {
    if (first_facet_[v] == kNoIndex) continue;
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], double(Pos(v)[k]));
      hi[k] = std::max(hi[k], double(Pos(v)[k]));
    }
  }
}

std::string Repairer::RoundedAwayNote() const {
  double lo[3], hi[3];
  ReferencedBox(lo, hi);
  const CoordinatePrecision p = PrecisionOfBox(lo, hi);
  if (!p.coarse()) return "";
  return absl::StrFormat(
      ", likely because the part lies far from the origin for its size: its coordinates reach "
      "%.6g, where 32-bit floats (how femsimp keeps positions) are %.3g apart, and the part "
      "measures %.3g across as read, so the file's detail was rounded away when it was read; "
      "translate the part near the origin",
      p.magnitude, p.spacing, p.diagonal);
}

absl::StatusOr<RepairResult> Repairer::Run(RawMesh& mesh) {
  nv_ = in_.num_vertices();
  nf_ = in_.num_faces();
  if (absl::Status s = CheckInput(); !s.ok()) return s;
  RepairReport& report = result_.report;
  report.input_vertices = nv_;
  report.input_facets = nf_;
  first_facet_.assign(nv_, kNoIndex);
  for (size_t c = 3 * nf_; c-- > 0;) first_facet_[in_.triangles[c]] = uint32_t(c / 3);

  Weld();
  FilterFacets();
  if (kept_.empty())
    return absl::InvalidArgumentError(absl::StrCat("mesh is empty after repair: all ", nf_,
                                                   " facets were degenerate or duplicates",
                                                   RoundedAwayNote()));
  if (!strict_) CloseTJunctions();
  BuildEdges();
  // A split can leave a facet's other open edge for the next call: a triangle has three.
  for (int call = 0; call < 3 && !strict_ && ZipTJunctions(); ++call) BuildEdges();
  if (!strict_ && FillHoles()) BuildEdges();
  // Before the orientation, whose cavity test needs the bodies closed: a dangling facet makes
  // its edge a seam. It also joined the body to a sheet that is no hole, so the hole fill left
  // the body's holes; without it they are filled.
  if (!strict_ && DropLoosePieces()) {
    BuildEdges();
    // The holes it left are looked at again: filled now, or reported again.
    result_.report.counts[static_cast<size_t>(RepairKind::kHoleLeft)] = 0;
    std::erase_if(result_.report.records,
                  [](const RepairRecord& r) { return r.kind == RepairKind::kHoleLeft; });
    if (FillHoles()) BuildEdges();
  }
  // Before the orientation too: with a body's copy beside it, a cavity's wall lay inside two
  // shells and was turned to face outward.
  if (!strict_ && DropDuplicateBodies()) BuildEdges();
  Orient();
  UnfoldEdges();
  SplitVertices();
  ReportEdges();
  if (!strict_) ReportVertices();
  // Records were added stage by stage; present them per kind, in input order within each.
  std::sort(report.records.begin(), report.records.end(),
            [](const RepairRecord& a, const RepairRecord& b) {
              return std::tie(a.kind, a.facet, a.vertex) < std::tie(b.kind, b.facet, b.vertex);
            });
  if (strict_) {
    if (report.num_changes() + report.num_defects_left() > 0) return StrictError();
  } else if (report.num_changes() > 0) {
    WriteOutput(mesh);
  }
  if (result_.facet_origin.empty()) {  // untouched: the identity
    result_.facet_origin.resize(nf_);
    for (uint32_t f = 0; f < nf_; ++f) result_.facet_origin[f] = f;
    result_.vertex_origin.resize(nv_);
    for (uint32_t v = 0; v < nv_; ++v) result_.vertex_origin[v] = v;
  }
  for (SeamEdge& seam : result_.seams)
    if (seam.a > seam.b) {
      std::swap(seam.a, seam.b);
      std::swap(seam.pa, seam.pb);
    }
  std::sort(result_.seams.begin(), result_.seams.end(), [](const SeamEdge& x, const SeamEdge& y) {
    return std::pair(x.a, x.b) < std::pair(y.a, y.b);
  });
  report.output_vertices = mesh.num_vertices();
  report.output_facets = mesh.num_faces();
  return std::move(result_);
}

}  // namespace

const char* RepairKindName(RepairKind kind) { return Info(kind).name; }

std::string SeamDetail(const std::array<double, 3>& to, size_t count,
                       const std::vector<uint32_t>& facets) {
  return absl::StrCat("to ", Point(to), ": shared by ", count, " facets (",
                      count == facets.size() ? "" : "pieces of input facets ",
                      absl::StrJoin(facets, ", "), ")");
}

bool IsRepairChange(RepairKind kind) {
  return kind != RepairKind::kSeamEdge && kind != RepairKind::kNonOrientable &&
         kind != RepairKind::kFoldLeft && kind != RepairKind::kContactLeft &&
         kind != RepairKind::kHoleLeft && kind != RepairKind::kCrossingLeft &&
         kind != RepairKind::kOverlapLeft && kind != RepairKind::kSharedShellLeft &&
         kind != RepairKind::kCount;
}

bool BlocksTheBuild(RepairKind kind) { return kind == RepairKind::kNonOrientable; }

std::string RepairRecord::ToString() const {
  std::string s = Info(kind).singular;
  switch (kind) {
    case RepairKind::kWeldedVertex:
    case RepairKind::kSplitVertex:
    case RepairKind::kUnreferencedVertex:
      if (vertex >= 0) {
        absl::StrAppend(&s, " ", vertex);
      } else {  // a point the imprint or the union added
        absl::StrAppend(&s, " (a point a repair step added)");
      }
      if (facet >= 0) absl::StrAppend(&s, " (facet ", facet, ")");
      break;
    case RepairKind::kSplitEdge:
      absl::StrAppend(&s, " of facet ", facet);
      break;
    case RepairKind::kFilledHole:
      absl::StrAppend(&s, " next to facet ", facet);
      break;
    case RepairKind::kImprintedContact:
    case RepairKind::kContactLeft:
    case RepairKind::kUnitedBodies:
    case RepairKind::kOverlapLeft:
      absl::StrAppend(&s, " of facet ", facet);
      break;
    case RepairKind::kDegenerateFacet:
    case RepairKind::kDuplicateFacet:
    case RepairKind::kFlippedFacet:
      absl::StrAppend(&s, " ", facet);
      break;
    default:  // edges and components: named by a facet on them
      absl::StrAppend(&s, " (facet ", facet, ")");
  }
  absl::StrAppend(&s, " at ", Point(at));
  if (!detail.empty()) absl::StrAppend(&s, ": ", detail);
  return s;
}

size_t RepairReport::num_changes() const {
  size_t n = 0;
  for (size_t k = 0; k < kNumRepairKinds; ++k)
    if (IsRepairChange(static_cast<RepairKind>(k))) n += counts[k];
  return n;
}

size_t RepairReport::num_defects_left() const {
  size_t n = 0;
  for (size_t k = 0; k < kNumRepairKinds; ++k)
    if (!IsRepairChange(static_cast<RepairKind>(k))) n += counts[k];
  return n;
}

std::string RepairReport::Summary() const {
  std::vector<std::string> changes, left;
  for (size_t k = 0; k < kNumRepairKinds; ++k) {
    if (counts[k] == 0) continue;
    const KindInfo& info = kKinds[k];
    std::string item = absl::StrCat(info.verb, " ", counts[k], " ",
                                    counts[k] == 1 ? info.noun : info.nouns, info.suffix);
    if (static_cast<RepairKind>(k) == RepairKind::kWeldedVertex)
      absl::StrAppend(&item, absl::StrFormat(" (tolerance %.3g of the diagonal = %.3g)",
                                             weld_tolerance_relative, weld_tolerance_absolute));
    (IsRepairChange(static_cast<RepairKind>(k)) ? changes : left).push_back(item);
  }
  std::string s = "repair: ";
  absl::StrAppend(&s, changes.empty() ? "no changes" : absl::StrJoin(changes, ", "));
  if (!left.empty()) absl::StrAppend(&s, "; ", absl::StrJoin(left, ", "));
  return s;
}

std::string RepairReport::Details() const {
  std::string s = Summary();
  for (size_t k = 0; k < kNumRepairKinds; ++k) {
    size_t listed = 0;
    for (const RepairRecord& record : records)
      if (static_cast<size_t>(record.kind) == k) {
        absl::StrAppend(&s, "\n  ", record.ToString());
        ++listed;
      }
    if (counts[k] > listed)
      absl::StrAppend(&s, "\n  ... and ", counts[k] - listed, " more ", kKinds[k].plural);
  }
  return s;
}

absl::StatusOr<RepairResult> RepairMesh(RawMesh& mesh, const RepairOptions& options) {
  // The repairer reads the input while it works and replaces the mesh only at the end.
  absl::StatusOr<RepairResult> repaired = Repairer(mesh, options).Run(mesh);
  if (!repaired.ok() || options.mode == RepairMode::kOff) return repaired;
  if (options.unite_overlaps) {
    repaired = UniteRepaired(mesh, options, *std::move(repaired));
    if (!repaired.ok()) return repaired;
  }
  if (options.take_out_crossings) {
    repaired = UncrossRepaired(mesh, options, *std::move(repaired));
    if (!repaired.ok()) return repaired;
  }
  if (!options.imprint) return repaired;
  return ImprintRepaired(mesh, options, *std::move(repaired));
}

}  // namespace femsimp
