#include "cloth_sim/core/model/model.h"

#include <stdexcept>
#include <string>

#include "cloth_sim/core/settings/settings_table.h"

namespace cloth_sim {

const char* springFamilyName(SpringFamily family) {
  switch (family) {
    case SpringFamily::kStructural: return "structural";
    case SpringFamily::kShear: return "shear";
    case SpringFamily::kBending: return "bending";
  }
  return "unknown";
}

void Springs::add(int i, int j, double rest, double k, SpringFamily f) {
  first.push_back(i);
  second.push_back(j);
  rest_length.push_back(rest);
  stiffness.push_back(k);
  family.push_back(f);
}

void Model::setFamilyStiffness(SpringFamily f, double k) {
  for (std::size_t s = 0; s < springs.size(); ++s) {
    if (springs.family[s] == f) springs.stiffness[s] = k;
  }
}

double Model::familyStiffness(SpringFamily f) const {
  for (std::size_t s = 0; s < springs.size(); ++s) {
    if (springs.family[s] == f) return springs.stiffness[s];
  }
  return 0.0;
}

const Setting& stiffnessSetting(SpringFamily family) {
  switch (family) {
    case SpringFamily::kStructural: return settings::kStructuralStiffness;
    case SpringFamily::kShear: return settings::kShearStiffness;
    case SpringFamily::kBending: break;
  }
  return settings::kBendingStiffness;
}

int Model::familySize(SpringFamily f) const {
  int n = 0;
  for (auto g : springs.family) n += (g == f) ? 1 : 0;
  return n;
}

namespace {
[[noreturn]] void fail(const std::string& what) { throw std::invalid_argument("model: " + what); }
}  // namespace

void Model::validate() const {
  const int n = particleCount();
  if (n == 0) fail("no particle");
  for (int i = 0; i < n; ++i) {
    settings::kParticleMass.require(mass[i], "model: mass[" + std::to_string(i) + "]");
  }
  const std::size_t m = springs.size();
  if (springs.second.size() != m || springs.rest_length.size() != m ||
      springs.stiffness.size() != m || springs.family.size() != m) {
    fail("spring arrays have different lengths");
  }
  for (std::size_t s = 0; s < m; ++s) {
    const int i = springs.first[s], j = springs.second[s];
    const std::string spring =
        "spring " + std::to_string(s) + " (" + std::to_string(i) + ", " + std::to_string(j) + ")";
    if (i < 0 || j < 0 || i >= n || j >= n) fail(spring + ": particle index out of range");
    if (i == j) fail(spring + ": joins a particle to itself");
    settings::kRestLength.require(springs.rest_length[s], "model: " + spring + " rest length");
    stiffnessSetting(springs.family[s])
        .require(springs.stiffness[s], "model: " + spring + " stiffness");
  }
  if (triangles.size() > 0 && (triangles.minCoeff() < 0 || triangles.maxCoeff() >= n)) {
    fail("triangle vertex index out of range");
  }
  // Any finite gravity: a scene's is bounded (settings::kGravity), a program may test extremes.
  if (!gravity.allFinite()) fail("gravity must be finite");
  settings::kDamping.require(damping, "model: damping");
}

State State::atRest(const Points& rest_positions) {
  State s;
  s.positions = rest_positions;
  s.velocities = Points::Zero(3, rest_positions.cols());
  return s;
}

bool State::allFinite() const { return positions.allFinite() && velocities.allFinite(); }

}  // namespace cloth_sim
