#include "engine/crossings.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <utility>
#include <vector>

#include "absl/strings/str_format.h"
#include "engine/fold.h"
#include "engine/planar_overlap.h"
#include "engine/transversal_crossing.h"
#include "engine/worker_pool.h"

namespace femsimp {
namespace {

// Faces cover at most this many cells on average (the cells grow until they do), and a cell
// coordinate fits a little over 20 bits, so that three pack into one key.
constexpr double kCellsPerFace = 8.0;
constexpr int kCellBits = 20;
constexpr double kPlaneTolerance = 1e-6;  // of the diagonal

struct Box {
  float lo[3], hi[3];
  bool Overlaps(const Box& o) const {
    for (int a = 0; a < 3; ++a)
      if (lo[a] > o.hi[a] || o.lo[a] > hi[a]) return false;
    return true;
  }
};

struct CellRange {
  int32_t lo[3], hi[3];
  int64_t count() const {
    return int64_t{hi[0] - lo[0] + 1} * (hi[1] - lo[1] + 1) * (hi[2] - lo[2] + 1);
  }
};

class Grid {
 public:
  Grid(const float (&origin)[3], double cell) : cell_(cell) {
    std::copy(origin, origin + 3, origin_);
  }
  CellRange Of(const Box& b) const {
    CellRange r;
    for (int a = 0; a < 3; ++a) {
      r.lo[a] = static_cast<int32_t>(std::floor((double{b.lo[a]} - origin_[a]) / cell_));
      r.hi[a] = static_cast<int32_t>(std::floor((double{b.hi[a]} - origin_[a]) / cell_));
    }
    return r;
  }
  double cell() const { return cell_; }

 private:
  float origin_[3];
  double cell_;
};

// A cell's key: its coordinates in (x, y, z) order, packed as tightly as the grid's extent
// allows (fewer radix passes than fixed fields).
struct CellKeys {
  uint64_t ny, nz;
  uint64_t Key(int64_t x, int64_t y, int64_t z) const {
    return (uint64_t(x) * ny + uint64_t(y)) * nz + uint64_t(z);
  }
  void Cell(uint64_t key, int32_t (&at)[3]) const {
    at[2] = int32_t(key % nz);
    at[1] = int32_t(key / nz % ny);
    at[0] = int32_t(key / nz / ny);
  }
};

// Whether t reaches through the other's plane by no more than `tolerance` on one of its sides:
// a face standing on another along a line (a block's side on the plate it touches) crosses it by
// its corners' rounding where the contact is tilted, a corner a float spacing below the plate's
// plane. As exported that is a contact, not a crossing.
bool TouchesWithinTolerance(const Triangle& t, const Triangle& other, double tolerance) {
  const DVec3 n = Cross(other.p[1] - other.p[0], other.p[2] - other.p[0]);
  const double length = Norm(n);
  if (length == 0.0) return false;
  double above = 0.0, below = 0.0;
  for (int k = 0; k < 3; ++k) {
    const double d = Dot(n, t.p[k] - other.p[0]) / length;
    above = std::max(above, d);
    below = std::max(below, -d);
  }
  return std::min(above, below) <= tolerance;
}

// Contacts exported apart are planar up to their corners' rounding to float.
double PlaneTolerance(const float (&lo)[3], const float (&hi)[3]) {
  const double magnitude = std::max({std::fabs(lo[0]), std::fabs(lo[1]), std::fabs(lo[2]),
                                     std::fabs(hi[0]), std::fabs(hi[1]), std::fabs(hi[2])});
  return std::max(kPlaneTolerance * std::hypot(double{hi[0]} - lo[0], double{hi[1]} - lo[1],
                                               double{hi[2]} - lo[2]),
                  16.0 * magnitude * std::numeric_limits<float>::epsilon());
}

// Whether s and t, which have an edge in common (equal ids), fold onto each other
// (engine/fold.h), and where: the middle of that edge.
std::optional<DVec3> Fold(const Triangle& s, const Triangle& t, double plane_tolerance) {
  const std::optional<std::pair<int, int>> apexes = OppositeApexes(s.id, t.id);
  if (!apexes) return std::nullopt;
  const auto [i, j] = *apexes;
  const DVec3 &a = s.p[(i + 1) % 3], &b = s.p[(i + 2) % 3];
  if (!IsFold(a, b, s.p[i], t.p[j], plane_tolerance)) return std::nullopt;
  return 0.5 * (a + b);
}

// The (cell, face) list sorted by cell, faces in their order within a cell: what sorting the
// pairs would give, by a stable radix sort on the cell keys' used bits (a million faces list
// about two million cells; std::sort took a third of the scan).
void SortByCell(std::vector<std::pair<uint64_t, uint32_t>>& listed) {
  uint64_t all = 0;
  for (const auto& e : listed) all |= e.first;
  std::vector<std::pair<uint64_t, uint32_t>> other(listed.size());
  constexpr int kDigitBits = 16;
  std::vector<size_t> start(size_t{1} << kDigitBits);
  for (int shift = 0; shift < 64 && (all >> shift) != 0; shift += kDigitBits) {
    const auto digit = [shift](uint64_t key) {
      return size_t((key >> shift) & ((uint64_t{1} << kDigitBits) - 1));
    };
    std::fill(start.begin(), start.end(), 0);
    for (const auto& e : listed) ++start[digit(e.first)];
    size_t at = 0;
    for (size_t& s : start) at += std::exchange(s, at);
    for (const auto& e : listed) other[start[digit(e.first)]++] = e;
    listed.swap(other);
  }
}

// What one stretch of cells found, kept apart so that the stretches run on any number of threads
// and are joined in cell order: the same lists, first pairs and sums as one thread's scan.
struct StretchFound {
  SoupCrossings found;
  CrossingPairLists lists;
  std::vector<double> overlap_areas;  // summed in order when joined
};

// A stretch of cells ends once its faces make this many pairs (a cell of n faces, n^2 / 2: a
// sliver output has few cells, crowded) or it holds kCellsPerStretch cells: by the data alone,
// so that the stretches (and a cut-short scan's end) do not depend on the thread count.
constexpr double kPairsPerStretch = 1 << 18;
constexpr uint32_t kCellsPerStretch = 512;
}  // namespace

double ContactPlaneTolerance(const RawMesh& soup) {
  float lo[3] = {HUGE_VALF, HUGE_VALF, HUGE_VALF}, hi[3] = {-HUGE_VALF, -HUGE_VALF, -HUGE_VALF};
  for (uint32_t v : soup.triangles)
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], soup.positions[3 * size_t{v} + a]);
      hi[a] = std::max(hi[a], soup.positions[3 * size_t{v} + a]);
    }
  return PlaneTolerance(lo, hi);
}

SoupCrossings FindCrossings(const RawMesh& soup, const CrossingScan& scan) {
  CrossingPairLists* const lists = scan.lists;
  const bool crossings_only = scan.crossings_only;
  WorkerPool* const pool = scan.pool;
  const size_t nf = soup.num_faces();
  if (nf < 2) return SoupCrossings{};
  const auto corner = [&](size_t f, int k) {
    return &soup.positions[3 * size_t{soup.triangles[3 * f + k]}];
  };
  // Per chunk of faces: their boxes, and the chunk's bounds and edge lengths, joined in chunk
  // order (the same sums on any number of threads).
  constexpr uint32_t kItemsPerChunk = 1 << 16;
  const uint32_t faces = static_cast<uint32_t>(nf);
  std::vector<Box> box(nf);
  struct Bounds {
    float lo[3] = {HUGE_VALF, HUGE_VALF, HUGE_VALF}, hi[3] = {-HUGE_VALF, -HUGE_VALF, -HUGE_VALF};
    double edges = 0;
  };
  std::vector<Bounds> chunk_bounds((nf + kItemsPerChunk - 1) / kItemsPerChunk);
  RunChunked(pool, faces, kItemsPerChunk, {}, [&](uint32_t first, uint32_t last) {
    Bounds& c = chunk_bounds[first / kItemsPerChunk];
    for (uint32_t f = first; f < last; ++f) {
      const float* p[3] = {corner(f, 0), corner(f, 1), corner(f, 2)};
      for (int a = 0; a < 3; ++a) {
        box[f].lo[a] = std::min({p[0][a], p[1][a], p[2][a]});
        box[f].hi[a] = std::max({p[0][a], p[1][a], p[2][a]});
        c.lo[a] = std::min(c.lo[a], box[f].lo[a]);
        c.hi[a] = std::max(c.hi[a], box[f].hi[a]);
      }
      for (int k = 0; k < 3; ++k) {
        const float* q = p[(k + 1) % 3];
        const double d[3] = {double{q[0]} - p[k][0], double{q[1]} - p[k][1],
                             double{q[2]} - p[k][2]};
        c.edges += std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
      }
    }
  });
  float lo[3] = {HUGE_VALF, HUGE_VALF, HUGE_VALF}, hi[3] = {-HUGE_VALF, -HUGE_VALF, -HUGE_VALF};
  double edges = 0;
  for (const Bounds& c : chunk_bounds) {
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], c.lo[a]);
      hi[a] = std::max(hi[a], c.hi[a]);
    }
    edges += c.edges;
  }
  const double extent =
      std::max({double{hi[0]} - lo[0], double{hi[1]} - lo[1], double{hi[2]} - lo[2], 1e-300});
  const double plane_tolerance = PlaneTolerance(lo, hi);
  // Faces in one plane up to that tolerance have boxes apart by it where the plane is on an axis
  // (a block's bottom a float spacing above the plate's top): for overlaps and folds the boxes
  // are widened by it. A certain crossing has a point inside both faces, so inside both exact
  // boxes: a scan for crossings only keeps them exact. Where the tolerance is the coordinates'
  // rounding on a part far from the origin (16 float spacings), widened boxes could each span
  // the part and make every pair a candidate.
  if (!crossings_only)
    RunChunked(pool, faces, kItemsPerChunk, {}, [&](uint32_t first, uint32_t last) {
      for (uint32_t f = first; f < last; ++f)
        for (int a = 0; a < 3; ++a) {
          box[f].lo[a] = std::nextafter(float(box[f].lo[a] - plane_tolerance), -HUGE_VALF);
          box[f].hi[a] = std::nextafter(float(box[f].hi[a] + plane_tolerance), HUGE_VALF);
        }
    });
  float origin[3];  // below every box
  for (int a = 0; a < 3; ++a)
    origin[a] = std::nextafter(float(lo[a] - plane_tolerance), -HUGE_VALF);
  for (const Box& b : box)
    for (int a = 0; a < 3; ++a) origin[a] = std::min(origin[a], b.lo[a]);
  Grid grid(origin, std::max(2.0 * edges / (3.0 * double(nf)), extent / double(1 << kCellBits)));
  std::vector<CellRange> range(nf);
  std::vector<double> chunk_covered(chunk_bounds.size());  // doubles: a box may cover 2^60
  for (;;) {  // large faces among small ones would each cover many cells
    RunChunked(pool, faces, kItemsPerChunk, {}, [&](uint32_t first, uint32_t last) {
      double covered = 0;
      for (uint32_t f = first; f < last; ++f)
        covered += double((range[f] = grid.Of(box[f])).count());
      chunk_covered[first / kItemsPerChunk] = covered;
    });
    double covered = 0;
    for (double c : chunk_covered) covered += c;
    if (covered <= kCellsPerFace * double(nf)) break;
    grid = Grid(origin, 2 * grid.cell());
  }
  int32_t cells_along[3] = {1, 1, 1};  // every box's cells are within [0, cells_along)
  for (const CellRange& r : range)
    for (int a = 0; a < 3; ++a) cells_along[a] = std::max(cells_along[a], r.hi[a] + 1);
  const CellKeys keys{uint64_t(cells_along[1]), uint64_t(cells_along[2])};
  // (cell, face), each face's cells at its own offset, then sorted by cell.
  std::vector<size_t> listed_at(nf + 1, 0);
  for (size_t f = 0; f < nf; ++f) listed_at[f + 1] = listed_at[f] + size_t(range[f].count());
  std::vector<std::pair<uint64_t, uint32_t>> listed(listed_at[nf]);
  RunChunked(pool, faces, kItemsPerChunk, {}, [&](uint32_t first, uint32_t last) {
    for (uint32_t f = first; f < last; ++f) {
      const CellRange& r = range[f];
      size_t at = listed_at[f];
      for (int32_t x = r.lo[0]; x <= r.hi[0]; ++x)
        for (int32_t y = r.lo[1]; y <= r.hi[1]; ++y)
          for (int32_t z = r.lo[2]; z <= r.hi[2]; ++z) listed[at++] = {keys.Key(x, y, z), f};
    }
  });
  SortByCell(listed);
  // What the pair loop reads of each listed face, in the list's order, so that each cell's
  // stretch can be sorted for the sweep below.
  struct Entry {
    Box box;
    int32_t first_cell[3];
    uint32_t face;
  };
  std::vector<Entry> entries(listed.size());
  RunChunked(pool, static_cast<uint32_t>(listed.size()), kItemsPerChunk, {},
             [&](uint32_t first, uint32_t last) {
               for (size_t i = first; i < last; ++i) {
                 const uint32_t f = listed[i].second;
                 entries[i] = {box[f], {range[f].lo[0], range[f].lo[1], range[f].lo[2]}, f};
               }
             });
  std::vector<size_t> cell_start;  // where each cell's stretch of `listed` begins, then the end
  for (size_t i = 0; i < listed.size(); ++i)
    if (i == 0 || listed[i].first != listed[i - 1].first) cell_start.push_back(i);
  const uint32_t cells = static_cast<uint32_t>(cell_start.size());
  cell_start.push_back(listed.size());
  // Each cell's faces by the low x of their boxes, so that the pair loop stops at the first
  // partner beyond a face's box (a cell of slivers holds hundreds of faces).
  RunChunked(pool, cells, kCellsPerStretch * 8, {}, [&](uint32_t first, uint32_t last) {
    for (uint32_t c = first; c < last; ++c)
      std::sort(entries.begin() + cell_start[c], entries.begin() + cell_start[c + 1],
                [](const Entry& a, const Entry& b) { return a.box.lo[0] < b.box.lo[0]; });
  });
  const auto triangle = [&](uint32_t f) {
    Triangle t;
    for (int k = 0; k < 3; ++k) {
      const float* p = corner(f, k);
      t.p[k] = {p[0], p[1], p[2]};
      t.id[k] = soup.triangles[3 * size_t{f} + k];
    }
    return t;
  };
  // Each face's plane (unit normal, offset) in floats: most pairs are far off each other's
  // planes, which this tells before OverlapInPlane's exact test (its rounding is far below the
  // doubled tolerance).
  std::vector<std::array<float, 4>> plane(nf);
  RunChunked(pool, static_cast<uint32_t>(nf), kItemsPerChunk, {},
             [&](uint32_t first, uint32_t last) {
               for (uint32_t f = first; f < last; ++f) {
                 const Triangle t = triangle(f);
                 const DVec3 n = Cross(t.p[1] - t.p[0], t.p[2] - t.p[0]);
                 const double length = Norm(n);
                 const DVec3 unit = length > 0.0 ? (1.0 / length) * n : DVec3{0, 0, 0};
                 plane[f] = {float(unit.x), float(unit.y), float(unit.z), float(Dot(unit, t.p[0]))};
               }
             });
  const auto near_plane = [&](uint32_t of, uint32_t other) {
    const std::array<float, 4>& e = plane[of];
    for (int k = 0; k < 3; ++k) {
      const float* q = corner(other, k);
      if (std::fabs(double{e[0]} * q[0] + double{e[1]} * q[1] + double{e[2]} * q[2] - e[3]) >
          2.0 * plane_tolerance)
        return false;
    }
    return true;
  };
  // Whether the corners of `other` reach through the plane of `of` by no more than the tolerance
  // on one side, by the float planes: a margin of 8 float spacings of the largest coordinate
  // covers their rounding, so that this says yes only where TouchesWithinTolerance would.
  double magnitude = 0;
  for (int k = 0; k < 3; ++k)
    magnitude = std::max({magnitude, std::fabs(double{lo[k]}), std::fabs(double{hi[k]})});
  const double sure_touch =
      plane_tolerance - 8.0 * magnitude * std::numeric_limits<float>::epsilon();
  const auto clearly_on_one_side = [&](uint32_t of, uint32_t other) {
    const std::array<float, 4>& e = plane[of];
    if (sure_touch <= 0 || (e[0] == 0 && e[1] == 0 && e[2] == 0)) return false;
    double above = 0, below = 0;
    for (int k = 0; k < 3; ++k) {
      const float* q = corner(other, k);
      const double d = double{e[0]} * q[0] + double{e[1]} * q[1] + double{e[2]} * q[2] - e[3];
      above = std::max(above, d);
      below = std::max(below, -d);
    }
    return std::min(above, below) <= sure_touch;
  };
  const auto shared_corners = [&](uint32_t a, uint32_t b) {
    int shared = 0;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        shared += soup.triangles[3 * size_t{a} + i] == soup.triangles[3 * size_t{b} + j];
    return shared;
  };
  // The pairs of one stretch of cells. A stretch stops once it has found more crossing pairs
  // than `stop_after` (its own count: what it finds does not depend on the other stretches).
  const bool listing = lists != nullptr;
  const size_t stop_after = scan.stop_after;
  const auto scan_stretch = [&](uint32_t first_cell, uint32_t last_cell, StretchFound& out) {
    SoupCrossings& found = out.found;
    for (uint32_t c = first_cell; c < last_cell; ++c) {
      const size_t begin = cell_start[c], end = cell_start[c + 1];
      if (end - begin < 2) continue;
      int32_t here[3];
      keys.Cell(listed[begin].first, here);
      for (size_t i = begin; i < end; ++i) {
        const Entry& a = entries[i];
        for (size_t j = i + 1; j < end; ++j) {
          const Entry& b = entries[j];
          if (b.box.lo[0] > a.box.hi[0]) break;
          if (!a.box.Overlaps(b.box)) continue;
          // A pair that shares several cells is tested in the first of them only.
          if (std::max(a.first_cell[0], b.first_cell[0]) != here[0] ||
              std::max(a.first_cell[1], b.first_cell[1]) != here[1] ||
              std::max(a.first_cell[2], b.first_cell[2]) != here[2])
            continue;
          // Faces with a common edge meet along it or fold within one plane: never a crossing.
          const int shared = shared_corners(a.face, b.face);
          if (shared > 2 || (shared == 2 && crossings_only)) continue;
          // Faces that do not reach through each other's planes are apart: the cheap tests
          // first, on the float planes, before the faces are built in doubles (most pairs end
          // here).
          const bool may_overlap = !crossings_only && shared == 0 && near_plane(a.face, b.face);
          const auto apart = [&] {
            return clearly_on_one_side(a.face, b.face) || clearly_on_one_side(b.face, a.face);
          };
          if (shared < 2 && !may_overlap && apart()) continue;
          const std::pair<uint32_t, uint32_t> pair = std::minmax(a.face, b.face);
          const Triangle first = triangle(pair.first), second = triangle(pair.second);
          if (shared == 2) {
            if (const std::optional<DVec3> at = Fold(first, second, plane_tolerance)) {
              SoupCrossings::Folds& fo = found.folds;
              if (listing) out.lists.folded.push_back(pair);
              if (fo.pairs++ == 0 || pair < std::pair(fo.face_a, fo.face_b)) {
                fo.face_a = pair.first;
                fo.face_b = pair.second;
                fo.at = {soup.origin[0] + at->x, soup.origin[1] + at->y, soup.origin[2] + at->z};
              }
            }
            continue;
          }
          if (const std::optional<PlanarOverlap> o =
                  may_overlap ? OverlapInPlane(first, second, plane_tolerance) : std::nullopt) {
            SoupCrossings::Overlaps& ov = found.overlaps;
            out.overlap_areas.push_back(o->area);
            if (listing) out.lists.overlapping.push_back(pair);
            if (ov.pairs++ == 0 || pair < std::pair(ov.face_a, ov.face_b)) {
              ov.face_a = pair.first;
              ov.face_b = pair.second;
              ov.at = {soup.origin[0] + o->at.x, soup.origin[1] + o->at.y,
                       soup.origin[2] + o->at.z};
            }
            continue;
          }
          if (may_overlap && apart()) continue;
          if (TouchesWithinTolerance(first, second, plane_tolerance) ||
              TouchesWithinTolerance(second, first, plane_tolerance))
            continue;
          const std::optional<DVec3> at = TransversalCrossing(first, second);
          if (!at) continue;
          if (listing) out.lists.crossing.push_back(pair);
          if (found.pairs++ == 0 || pair < std::pair(found.face_a, found.face_b)) {
            found.face_a = pair.first;
            found.face_b = pair.second;
            found.at = {soup.origin[0] + at->x, soup.origin[1] + at->y, soup.origin[2] + at->z};
          }
          if (found.pairs > stop_after) return;
        }
      }
    }
  };
  // Stretches are taken in order; once the crossings listed exceed `stop_after` the ones not yet
  // begun are left. Those begun before are complete (or cut by their own count), so the join
  // below ends at the same stretch on any number of threads.
  std::vector<uint32_t> stretch_start;  // the first cell of each stretch, then `cells`
  double pairs_in_stretch = 0;
  for (uint32_t c = 0; c < cells; ++c) {
    if (c == 0 || pairs_in_stretch >= kPairsPerStretch ||
        c - stretch_start.back() >= kCellsPerStretch) {
      stretch_start.push_back(c);
      pairs_in_stretch = 0;
    }
    const double n = double(cell_start[c + 1] - cell_start[c]);
    pairs_in_stretch += 0.5 * n * n;
  }
  const uint32_t num_stretches = static_cast<uint32_t>(stretch_start.size());
  stretch_start.push_back(cells);
  std::vector<StretchFound> stretches(num_stretches);
  std::vector<char> done(num_stretches, 0);
  std::atomic<size_t> crossings_listed{0};
  RunChunked(pool, num_stretches, 1, {}, [&](uint32_t k, uint32_t) {
    if (crossings_listed.load(std::memory_order_relaxed) > stop_after) return;
    scan_stretch(stretch_start[k], stretch_start[k + 1], stretches[k]);
    crossings_listed.fetch_add(stretches[k].found.pairs, std::memory_order_relaxed);
    done[k] = 1;
  });
  SoupCrossings found;
  const auto keep_first = [](uint64_t& pairs, uint32_t& a, uint32_t& b, std::array<double, 3>& at,
                             uint64_t more, uint32_t more_a, uint32_t more_b,
                             const std::array<double, 3>& more_at) {
    if (more == 0) return;
    if (pairs == 0 || std::pair(more_a, more_b) < std::pair(a, b)) {
      a = more_a;
      b = more_b;
      at = more_at;
    }
    pairs += more;
  };
  for (size_t k = 0; k < stretches.size() && done[k]; ++k) {
    const StretchFound& s = stretches[k];
    keep_first(found.pairs, found.face_a, found.face_b, found.at, s.found.pairs, s.found.face_a,
               s.found.face_b, s.found.at);
    const SoupCrossings::Overlaps& so = s.found.overlaps;
    SoupCrossings::Overlaps& o = found.overlaps;
    keep_first(o.pairs, o.face_a, o.face_b, o.at, so.pairs, so.face_a, so.face_b, so.at);
    for (double area : s.overlap_areas) o.area += area;
    const SoupCrossings::Folds& sf = s.found.folds;
    SoupCrossings::Folds& fo = found.folds;
    keep_first(fo.pairs, fo.face_a, fo.face_b, fo.at, sf.pairs, sf.face_a, sf.face_b, sf.at);
    if (lists != nullptr)
      for (auto [to, from] : {std::pair(&lists->crossing, &s.lists.crossing),
                              std::pair(&lists->overlapping, &s.lists.overlapping),
                              std::pair(&lists->folded, &s.lists.folded)})
        to->insert(to->end(), from->begin(), from->end());
    if (found.pairs > stop_after) {
      found.cut_short = true;  // enough to know: the count is a floor
      break;
    }
  }
  return found;
}

SoupCrossings CheckOutputCrossings(const RawMesh& output, int threads) {
  WorkerPool pool(std::max(threads, 1));
  return FindCrossings(output, {.stop_after = kEnoughCrossingPairs, .pool = &pool});
}

std::string DescribeCrossings(const SoupCrossings& c) {
  if (c.cut_short)
    return absl::StrFormat(
        "at least %u face pairs cross (the check stopped there: a soup of facets, or bodies "
        "exported overlapping; the first it found: faces %u and %u, at (%.6g, %.6g, %.6g))",
        c.pairs, c.face_a, c.face_b, c.at[0], c.at[1], c.at[2]);
  return absl::StrFormat("%u face pair%s cross (the first: faces %u and %u, at (%.6g, %.6g, %.6g))",
                         c.pairs, c.pairs == 1 ? "" : "s", c.face_a, c.face_b, c.at[0], c.at[1],
                         c.at[2]);
}

std::string DescribeOverlaps(const SoupCrossings& c) {
  const SoupCrossings::Overlaps& o = c.overlaps;
  return absl::StrFormat(
      "%s%u face pair%s overlap in their plane, over an area of %.6g (the first: faces %u and "
      "%u, at (%.6g, %.6g, %.6g)): bodies exported apart that touch, each with its own "
      "triangulation of the contact",
      c.cut_short ? "at least " : "", o.pairs, o.pairs == 1 ? "" : "s", o.area, o.face_a, o.face_b,
      o.at[0], o.at[1], o.at[2]);
}

std::string DescribeFolds(const SoupCrossings& c) {
  const SoupCrossings::Folds& f = c.folds;
  return absl::StrFormat(
      "%s%u face pair%s lie on each other in their plane, one of each turned over (the first: "
      "faces %u and %u, along their common edge at (%.6g, %.6g, %.6g))",
      c.cut_short ? "at least " : "", f.pairs, f.pairs == 1 ? "" : "s", f.face_a, f.face_b, f.at[0],
      f.at[1], f.at[2]);
}

}  // namespace femsimp
