/// @file mesh_file.h
/// Triangle meshes from the files robots describe their bodies with: Wavefront OBJ and STL
/// (binary or ASCII), chosen by the file's extension.
#pragma once

#include <string>

#include "cloth_sim/core/model/triangle_mesh.h"

namespace cloth_sim {

/// Parses STL @p bytes (binary, or ASCII when it starts with "solid" and is not a valid binary
/// file), merging vertices that are bit-identical. @p source names it in errors. Throws
/// std::invalid_argument on a truncated or malformed file or one without a triangle.
TriangleMesh parseStl(const std::string& bytes, const std::string& source);
/// Reads an OBJ (.obj) or STL (.stl) file, any case of the extension; units as in the file
/// (m unless scaled). Throws std::invalid_argument naming the file for another extension, a
/// file that cannot be read or a malformed one.
TriangleMesh loadMeshFile(const std::string& path);

}  // namespace cloth_sim
