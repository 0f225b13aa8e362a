// The repair stage: turns a triangle soup as CAD exports write it into one that Mesh::Build
// accepts, or says exactly what it could not fix, and reports every change it made.
//
// Facet and vertex numbers in reports are 0-based indices into the RawMesh passed to RepairMesh,
// that is, the order in which the reader delivered them: the file's facet order for STL, OFF and
// PLY triangle files (a reader that triangulates polygons numbers the triangles it makes).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "absl/status/statusor.h"
#include "engine/raw_mesh.h"

namespace femsimp {

enum class RepairMode {
  kOff,  // strict: change nothing; fail naming every defect Mesh::Build would refuse
  kOn,   // repair what can be repaired without moving a point, and report it
};

// Which openings of a surface repair closes (a component is closed only when all of its can be).
enum class HoleFill {
  kSmall,   // loops of at most 6 edges and a tenth of the surface's area: facets an exporter lost
  kPlanar,  // also loops in one plane, as a whole face an exporter dropped leaves (a solid's
            // face with its holes: the loops of one plane filled together)
  kNone,    // none: every opening stays, reported
};

struct RepairOptions {
  RepairMode mode = RepairMode::kOn;
  // Vertices closer than this fraction of the bounding-box diagonal (of the referenced vertices)
  // are welded into the lowest-numbered one. 0 welds exact duplicates only.
  double weld_tolerance = 1e-7;
  // Closed components are turned so that the mesh bounds a volume: outward, and inward where
  // one lies inside an odd number of others (a cavity's wall faces into the cavity).
  bool orient_outward = true;
  // Per kind, how many changes are recorded one by one (counts are always complete).
  size_t max_records_per_kind = 20;
  // Bodies exported apart that touch in a plane get their contact re-tiled as one surface
  // shared by both (engine/imprint.h), after the other repairs; off: such contacts stay as
  // exported (the output's report names them).
  bool imprint = false;
  HoleFill fill_holes = HoleFill::kSmall;
  // Closed bodies that cross each other (a part exported as solids never fused) are replaced by
  // their union (engine/overlap_union.h), after the first repairs and before crossings are taken
  // out; off: they stay crossing (the report names them).
  bool unite_overlaps = false;
  // Facets of one surface that cross each other are taken out with the facets around them and
  // the hole closed again (engine/crossing_repair.h), after the other repairs. Off only where a
  // step runs the repairs again on what it made.
  bool take_out_crossings = true;
  // Open sheets beside the bodies (engine/loose_pieces.h) whose area is under this share of the
  // bodies' area are removed; 0 keeps them.
  double loose_piece_share = 0.01;
  // Closed bodies written twice (engine/duplicate_bodies.h): a later body within this share of
  // the bodies' mean thickness 2V/A of an earlier one is removed; 0 keeps them.
  double duplicate_body_offset = 0.1;
  // Threads the scan for crossings may use: the caller's SimplifyOptions::threads (the CLI and
  // the server set it); the result is the same on any number.
  int threads = 1;
};

enum class RepairKind : int {
  // Changes (kOn).
  kWeldedVertex,        // merged into a coincident vertex (within the weld tolerance)
  kStitchedEdge,        // two boundary edges joined into one by the weld (a crack closed)
  kDegenerateFacet,     // removed: repeats a vertex (after welding), zero area or a needle
  kSplitEdge,           // a facet's edge split at the T vertex of a sliver it faced
  kDuplicateFacet,      // removed: same three vertices as an earlier facet, either orientation
  kFlippedFacet,        // turned to agree with its component (or with the outward orientation)
  kReversedComponent,   // a closed component that faced the wrong way: inside out, or a cavity's
                        // wall facing out (its facets are also listed)
  kSplitVertex,         // a vertex where several fans met, given one copy per fan
  kUnreferencedVertex,  // dropped: no facet uses it (any more)
  kFilledHole,          // a loop of open edges closed by new facets (a facet missing; with
                        // HoleFill::kPlanar also a flat face missing)
  kImprintedContact,    // bodies exported apart that touch: their contact re-tiled as one shared
                        // surface (RepairOptions::imprint)
  kUnfoldedEdge,        // two facets lying on each other in their plane, one turned over (a
                        // fold, engine/fold.h): their common edge flipped to the other diagonal
  kCrossingRemoved,     // facets of one surface crossing each other: a patch around them taken
                        // out and its rim closed again (engine/crossing_repair.h)
  kUnitedBodies,        // closed bodies crossing each other replaced by their union
                        // (RepairOptions::unite_overlaps)
  kLoosePiece,          // removed: a small open sheet beside the bodies, joined to nothing or
                        // dangling from an edge (a stray facet, a leftover face:
                        // engine/loose_pieces.h)
  kDuplicateBody,       // removed: a closed body repeating an earlier one within a small share
                        // of its thickness (engine/duplicate_bodies.h)
  // Left in place.
  kSharedShell,      // a closed surface every facet of which came twice, facing both ways,
                     // inside another body: the surface two bodies share (an insert, a core,
                     // a part under a coating), kept and simplified once, each body a part
                     // (engine/enclosed_parts.h), written once per body again by OutputMesh
  kSeamEdge,         // an edge of 3 or more facets: kept, listed in RepairResult::seams
  kNonOrientable,    // a component that no choice of facet orientations makes consistent (the
                     // mesh still fails Mesh::Build)
  kFoldLeft,         // a fold no flip unfolds (the flip would turn a facet over, join two face
                     // groups, or make an edge that exists): kept; FE meshers refuse it
  kContactLeft,      // a contact the imprint could not re-tile: it stays as exported
  kHoleLeft,         // a loop of open edges of a surface that it would close with under half its
                     // area, too large to fill (a face missing): the output stays open
  kCrossingLeft,     // facets crossing each other that no patch took out (two bodies overlapping, a
                     // thin wall tessellated coarser than its thickness): FE meshers refuse them
  kOverlapLeft,      // bodies crossing each other that the union left (one not closed, crossing
                     // itself, or a union that is not a closed surface): FE meshers refuse them
  kSharedShellLeft,  // such a surface (kSharedShell) where the parts cannot be made (the mesh
                     // has seams, the inner body holds another surface, or the outer one is no
                     // body): kept once as the wall of a cavity, the body inside it not in the mass
  kCount,
};
inline constexpr size_t kNumRepairKinds = static_cast<size_t>(RepairKind::kCount);

// Stable lower-case name of a kind ("welded_vertex", ...), for JSON, metrics and messages.
const char* RepairKindName(RepairKind kind);
// True for the kinds RepairMesh changes; false for the defects it leaves in place.
bool IsRepairChange(RepairKind kind);
// True for what is left in place that Mesh::Build refuses (a non-orientable component); seams
// and contacts left apart are kept and simplified as they are.
bool BlocksTheBuild(RepairKind kind);
// A seam record's detail: "to (x, y, z): shared by N facets (f1, f2, ...)"; where fewer facets
// than N are listed, pieces of them share it ("(pieces of input facets f1, f2)").
std::string SeamDetail(const std::array<double, 3>& to, size_t count,
                       const std::vector<uint32_t>& facets);

// One change (or defect), located for a user who only has the input file.
struct RepairRecord {
  RepairKind kind;
  int64_t facet = -1;   // input facet it concerns (for vertex kinds: the first facet using it)
  int64_t vertex = -1;  // input vertex it concerns, for vertex and edge kinds
  std::array<double, 3> at{};  // where: the vertex, the facet's centroid, the edge's first end
  std::string detail;          // what exactly, e.g. "merged into vertex 3 (distance 2e-08)"

  std::string ToString() const;  // "flipped facet 5 at (0, 0.5, 0.5): ..."
};

struct RepairReport {
  std::array<size_t, kNumRepairKinds> counts{};
  // The first max_records_per_kind found of each kind, ordered by kind, then facet, then vertex.
  std::vector<RepairRecord> records;
  double diagonal = 0;  // bounding-box diagonal of the referenced vertices
  double weld_tolerance_relative = 0;
  double weld_tolerance_absolute = 0;  // = relative * diagonal
  size_t input_vertices = 0, input_facets = 0, output_vertices = 0, output_facets = 0;

  size_t count(RepairKind kind) const { return counts[static_cast<size_t>(kind)]; }
  size_t num_changes() const;       // sum of the counts of the change kinds
  size_t num_defects_left() const;  // sum of the counts of the kinds left in place
  // One line of counts, e.g. "repair: welded 3 vertices (tolerance 1e-07 of the diagonal =
  // 1.7e-07), flipped 2 facets; kept 4 non-manifold edges as seams", or "repair: no changes".
  std::string Summary() const;
  // Summary() and then one line per record, with "... and N more" per kind beyond the cap.
  std::string Details() const;
};

// A non-manifold edge left in place: the lead's seam machinery locks these.
struct SeamEdge {
  uint32_t a = 0, b = 0;  // output vertex indices, a < b
  std::array<float, 3> pa{}, pb{};
  std::vector<uint32_t> facets;  // input facet indices of the facets sharing it
};

inline constexpr uint32_t kNoInputVertex = 0xffffffffu;

struct RepairResult {
  RepairReport report;
  std::vector<SeamEdge> seams;  // every non-manifold edge of the output, ordered by (a, b)
  // Provenance of the output (empty in kOff mode, where the mesh is left as it was): the input
  // facet of each output facet (for a facet that fills a hole: the facet across the hole's first
  // edge, whose group and fields it takes; for an imprinted contact's: the facet it lies in), and
  // the input vertex of each output vertex (split copies name the vertex they were split from;
  // points an imprint added where edges cross: kNoInputVertex).
  std::vector<uint32_t> facet_origin, vertex_origin;
  // The closed surfaces two bodies share whole (the kSharedShellLeft records, in their order),
  // kept once and oriented into the inner body, as the outer body's copy faced. PrepareMesh makes
  // them parts where it can (and the records kSharedShell).
  struct SharedShell {
    uint32_t facet;  // an output facet of it
    // Per face group of the kept facets, the group of the copies removed (the inner body's); the
    // kept facets take the group of the copy that faced as they face now.
    std::vector<std::pair<uint32_t, uint32_t>> twin_groups;
  };
  std::vector<SharedShell> shared_shells;
};

// Repairs `mesh` in place (kOn) in this order: weld coincident vertices; remove degenerate, then
// duplicate facets; close T-junctions; zip T-junction cracks; fill small holes; orient each
// component consistently (closed ones to bound a volume: outward, cavities inward); unfold
// folds (below); split
// non-manifold vertices; drop unreferenced vertices; with `unite_overlaps`, replace closed bodies
// that cross each other by their union (engine/overlap_union.h); take out facets of one surface
// that cross each other (engine/crossing_repair.h); with `imprint`, re-tile the planar contacts
// of bodies exported apart (engine/imprint.h) and check the result with the steps above again
// (their changes, if any, are counted too; records then name the input facets the changed
// facets came from). Faces keep their input order, groups and
// fields (hole fills are appended); kept vertices keep their order, split copies are appended. A
// mesh with nothing to repair comes back untouched (byte-identical) with an empty report.
// Non-manifold edges are kept and reported.
//
// T-junctions: a zero-area facet (a, t, b) with three distinct vertices, t between a and b (or a
// needle: t within the weld tolerance of edge a-b, as a single-precision export writes it), that
// shares an edge a-t or t-b with another facet closes a T-junction; removing it alone would open
// a crack along a-b. So each facet (a, b, c) across its longest edge a-b is split at t into
// (a, t, c) and (t, b, c) (its orientation, group and field values), both in its place, first
// then second (a half split again is replaced in place the same way), and the sliver is removed.
// Slivers along one edge (a chain, sharing middle vertices) are taken one after another, each
// once no other sliver is left on its longest edge. A split that would make a zero-area facet or
// an edge that already exists is not made: the sliver is then only removed, and its record says
// why.
//
// T-junction cracks (no sliver): an open edge is split at the vertices of the open edges along
// it (within an eighth of its length: on a curved seam they are off its chord), where the
// whole crack then closes (docs/FIDELITY.md, "Repair"). Holes: a component whose
// every open loop is small (at most 6 edges, a tenth of its area) gets them filled with the
// least-area triangulation that adds no existing edge; with fill_holes kPlanar, loops in one
// plane are filled too (engine/flat_openings.h), with kNone none is. Loops left open are
// reported (kHoleLeft) where they would close their surface with under half its area.
//
// Folds (engine/fold.h): a manifold edge whose two facets lie in one plane, within the contact
// tolerance (engine/crossings.h) or an opening angle of 0.06 degrees, and face opposite ways is
// flipped to the quad's other diagonal where both new facets then face the pair's way, the
// facets share their group and field values and the new edge is not one already; flips repeat
// (a fan turned over unfolds one edge at a time) until none is left or none helps, at most 8
// rounds. What is left is reported (kFoldLeft) and kept. No point moves and the region covered,
// counted with orientation, is the same, so volume and moments stay as they were.
//
// Errors (InvalidArgument, the mesh untouched): what no repair can fix (indices out of range,
// referenced non-finite coordinates, inconsistent array sizes, empty input or output), each
// occurrence listed; in kOff mode also every defect Mesh::Build would refuse (degenerate,
// duplicate and inconsistently oriented facets, non-manifold vertices and edges), by kind,
// facet and coordinates, capped per kind with "and N more".
absl::StatusOr<RepairResult> RepairMesh(RawMesh& mesh, const RepairOptions& options);

}  // namespace femsimp
