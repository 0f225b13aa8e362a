// gmsh MSH files: femsimp's reader of versions 2.2 and 4.1, ASCII and binary (msh_reader.cc), and
// its writer of version 4.1 ASCII (msh_writer.cc).
//
// Faces are the 3-node triangles (element type 2); their physical group is their face group (the
// uint32 id is the physical tag): in 4.1 the first physical tag of the surface entity they belong
// to ($Entities, or $PartitionedEntities in a partitioned mesh), in 2.2 the element's first tag.
// $PhysicalNames of dimension 2 are the groups' names (GroupNames, as OBJ's). Every other element
// (points, lines, quadrangles, volumes, higher-order elements) is left out and counted in a
// warning, and so are the nodes no triangle uses and post-processing sections ($NodeData,
// $ElementData, ...): femsimp carries no face fields in MSH files.
#pragma once

#include <string>

#include "absl/status/status.h"
#include "absl/strings/string_view.h"
#include "engine/io/face_data.h"
#include "engine/io/mesh_readers.h"
#include "engine/raw_mesh.h"

namespace femsimp {

// Reads the file into `out` (nodes in file order, unused ones dropped; faces in file order). A
// file it cannot read is refused naming the line (ASCII) or byte offset (binary): truncation, a
// malformed or unclosed section, an unknown version, an element naming a node $Nodes does not
// define, a coordinate that is not a finite float, a binary file of unknown byte order.
absl::Status ParseMsh(absl::string_view data, ParsedMeshFile* out);

// MSH 4.1 ASCII, as gmsh writes it: $PhysicalNames for the groups named in `names`, one surface
// entity per face group (its physical tag the group id; group 0 of a mesh with groups has
// physical tag 0, which the reader reads back as group 0), every node in one block, the faces as
// 3-node triangles, each group's in the mesh's order.
std::string MshText(const RawMesh& mesh, const GroupNames& names);

// What CheckFaceData asks of the names of the mesh's groups in an MSH file: at most 127
// characters on one line without a double quote, as gmsh reads them.
absl::Status CheckMshGroupNames(const RawMesh& mesh, const GroupNames& names);

}  // namespace femsimp
