#include "cloth_sim/core/model/model.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

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
    if (!std::isfinite(mass[i]) || mass[i] <= 0.0) {
      std::ostringstream s;
      s << "mass[" << i << "] = " << mass[i] << " kg must be finite and > 0";
      fail(s.str());
    }
  }
  const std::size_t m = springs.size();
  if (springs.second.size() != m || springs.rest_length.size() != m ||
      springs.stiffness.size() != m || springs.family.size() != m) {
    fail("spring arrays have different lengths");
  }
  for (std::size_t s = 0; s < m; ++s) {
    const int i = springs.first[s], j = springs.second[s];
    std::ostringstream msg;
    msg << "spring " << s << " (" << i << ", " << j << "): ";
    if (i < 0 || j < 0 || i >= n || j >= n) fail(msg.str() + "particle index out of range");
    if (i == j) fail(msg.str() + "joins a particle to itself");
    if (!std::isfinite(springs.rest_length[s]) || springs.rest_length[s] <= 0.0) {
      msg << "rest length " << springs.rest_length[s] << " m must be finite and > 0";
      fail(msg.str());
    }
    if (!std::isfinite(springs.stiffness[s]) || springs.stiffness[s] < 0.0) {
      msg << "stiffness " << springs.stiffness[s] << " N/m must be finite and >= 0";
      fail(msg.str());
    }
  }
  if (triangles.size() > 0 && (triangles.minCoeff() < 0 || triangles.maxCoeff() >= n)) {
    fail("triangle vertex index out of range");
  }
  if (!gravity.allFinite()) fail("gravity must be finite");
  if (!std::isfinite(damping) || damping < 0.0) {
    fail("damping = " + std::to_string(damping) + " 1/s must be finite and >= 0");
  }
}

State State::atRest(const Points& rest_positions) {
  State s;
  s.positions = rest_positions;
  s.velocities = Points::Zero(3, rest_positions.cols());
  return s;
}

bool State::allFinite() const { return positions.allFinite() && velocities.allFinite(); }

}  // namespace cloth_sim
