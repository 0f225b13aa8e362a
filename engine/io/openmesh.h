// OpenMesh headers (the OFF and STL writers), wrapped: GCC 12 reports -Wmaybe-uninitialized false
// positives inside OpenMesh's Property.hh, which we silence here and only here.
#pragma once

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#pragma GCC diagnostic pop
