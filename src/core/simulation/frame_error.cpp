#include "cloth_sim/core/simulation/frame_error.h"

#include <cmath>

namespace cloth_sim {

void FrameError::begin(Eigen::Index particles) {
  sum_.setZero(3, particles);
  counted_.assign(static_cast<std::size_t>(particles), 0);
}

void FrameError::add(const Points& errors, const std::vector<char>& estimated) {
  if (errors.cols() != sum_.cols()) begin(errors.cols());
  for (Eigen::Index i = 0; i < errors.cols(); ++i) {
    if (!estimated[i]) continue;
    sum_.col(i) += errors.col(i);
    counted_[i] = 1;
  }
}

double FrameError::rms() const {
  double sum = 0.0;
  int count = 0;
  for (Eigen::Index i = 0; i < sum_.cols(); ++i) {
    if (!counted_[i]) continue;
    sum += sum_.col(i).squaredNorm();
    ++count;
  }
  return count > 0 ? std::sqrt(sum / count) : 0.0;
}

}  // namespace cloth_sim
