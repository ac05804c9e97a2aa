#include "cloth_sim/core/model/mesh_file.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace cloth_sim {
namespace {

/// Collects triangles, merging bit-identical vertices.
class MeshAssembler {
 public:
  void corner(const Vec3& p) {
    const std::array<double, 3> key{p.x(), p.y(), p.z()};
    auto [it, inserted] = index_.emplace(key, static_cast<int>(points_.size()));
    if (inserted) points_.push_back(p);
    corners_.push_back(it->second);
  }
  TriangleMesh mesh(const std::string& source) const {
    if (corners_.empty() || corners_.size() % 3 != 0) {
      throw std::invalid_argument(source + ": the STL file has no triangle");
    }
    TriangleMesh m;
    m.vertices.resize(3, static_cast<Eigen::Index>(points_.size()));
    for (std::size_t k = 0; k < points_.size(); ++k) m.vertices.col(k) = points_[k];
    m.triangles.resize(3, static_cast<Eigen::Index>(corners_.size() / 3));
    for (std::size_t k = 0; k < corners_.size(); ++k) m.triangles(k % 3, k / 3) = corners_[k];
    return m;
  }

 private:
  std::map<std::array<double, 3>, int> index_;
  std::vector<Vec3> points_;
  std::vector<int> corners_;
};

bool isBinaryStl(const std::string& bytes) {
  if (bytes.size() < 84) return false;
  std::uint32_t count = 0;
  std::memcpy(&count, bytes.data() + 80, 4);
  return bytes.size() == 84 + 50 * static_cast<std::size_t>(count);
}

TriangleMesh parseBinary(const std::string& bytes, const std::string& source) {
  std::uint32_t count = 0;
  std::memcpy(&count, bytes.data() + 80, 4);
  MeshAssembler out;
  for (std::uint32_t t = 0; t < count; ++t) {
    const char* facet = bytes.data() + 84 + 50 * static_cast<std::size_t>(t);
    for (int c = 0; c < 3; ++c) {
      float xyz[3];
      std::memcpy(xyz, facet + 12 + 12 * c, sizeof xyz);  // after the normal
      out.corner(Vec3(xyz[0], xyz[1], xyz[2]));
    }
  }
  return out.mesh(source);
}

TriangleMesh parseAscii(const std::string& bytes, const std::string& source) {
  std::istringstream in(bytes);
  std::string word;
  MeshAssembler out;
  int in_facet = 0;
  while (in >> word) {
    std::transform(word.begin(), word.end(), word.begin(), [](unsigned char c) { return std::tolower(c); });
    if (word == "vertex") {
      Vec3 p;
      if (!(in >> p.x() >> p.y() >> p.z())) {
        throw std::invalid_argument(source + ": a vertex of the STL file is not three numbers");
      }
      out.corner(p);
      ++in_facet;
    } else if (word == "endfacet") {
      if (in_facet != 3) {
        throw std::invalid_argument(source + ": an STL facet has " + std::to_string(in_facet) +
                                    " vertices, not 3");
      }
      in_facet = 0;
    }
  }
  return out.mesh(source);
}

}  // namespace

TriangleMesh parseStl(const std::string& bytes, const std::string& source) {
  if (isBinaryStl(bytes)) return parseBinary(bytes, source);
  if (bytes.compare(0, 5, "solid") == 0) return parseAscii(bytes, source);
  throw std::invalid_argument(source + ": not an STL file (a binary one's size does not match its "
                              "triangle count, and it does not start with 'solid')");
}

TriangleMesh loadMeshFile(const std::string& path) {
  std::string ext = path.size() >= 4 ? path.substr(path.size() - 4) : "";
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  if (ext == ".obj") return loadObj(path);
  if (ext != ".stl") {
    throw std::invalid_argument(path + ": a mesh file must be .obj or .stl");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::invalid_argument(path + ": cannot open the STL file");
  std::stringstream bytes;
  bytes << in.rdbuf();
  return parseStl(bytes.str(), path);
}

}  // namespace cloth_sim
