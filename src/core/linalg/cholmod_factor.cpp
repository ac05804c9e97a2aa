#include "cloth_sim/core/linalg/cholmod_factor.h"

#include <algorithm>
#include <cstring>
#include <utility>
#include <stdexcept>
#include <string>

#include <cholmod.h>

namespace cloth_sim {

struct CholmodFactor::Impl {
  cholmod_common common;
  cholmod_factor* factor = nullptr;
  cholmod_dense* x = nullptr;  // solve2 workspaces, reused
  cholmod_dense* y = nullptr;
  cholmod_dense* e = nullptr;
  bool ok = false;

  explicit Impl(Kind kind) {
    cholmod_start(&common);
    common.print = 0;  // a non-positive-definite matrix is an expected outcome, not a message
    common.supernodal = kind == Kind::kSupernodal ? CHOLMOD_SUPERNODAL : CHOLMOD_SIMPLICIAL;
    common.final_ll = 1;  // L L^T rather than L D L^T: what exportLower wants
    // Try AMD and METIS nested dissection, keep the sparser factor (cloth graphs: METIS wins
    // by 5-10 % above a few thousand nodes, AMD below).
    common.nmethods = 2;
    common.method[0].ordering = CHOLMOD_AMD;
    common.method[1].ordering = CHOLMOD_METIS;
  }
  ~Impl() {
    if (factor != nullptr) cholmod_free_factor(&factor, &common);
    if (x != nullptr) cholmod_free_dense(&x, &common);
    if (y != nullptr) cholmod_free_dense(&y, &common);
    if (e != nullptr) cholmod_free_dense(&e, &common);
    cholmod_finish(&common);
  }

  /// A read-only CHOLMOD view of an Eigen matrix; stype -1: only the lower triangle is used.
  static cholmod_sparse view(const Eigen::SparseMatrix<double>& a) {
    if (!a.isCompressed()) throw std::invalid_argument("CholmodFactor: matrix must be compressed");
    cholmod_sparse s{};
    s.nrow = static_cast<std::size_t>(a.rows());
    s.ncol = static_cast<std::size_t>(a.cols());
    s.nzmax = static_cast<std::size_t>(a.nonZeros());
    s.p = const_cast<int*>(a.outerIndexPtr());
    s.i = const_cast<int*>(a.innerIndexPtr());
    s.x = const_cast<double*>(a.valuePtr());
    s.stype = -1;
    s.itype = CHOLMOD_INT;
    s.xtype = CHOLMOD_REAL;
    s.dtype = CHOLMOD_DOUBLE;
    s.sorted = 1;
    s.packed = 1;
    return s;
  }
};

CholmodFactor::CholmodFactor(Kind kind) : impl_(std::make_unique<Impl>(kind)) {}
CholmodFactor::~CholmodFactor() = default;
CholmodFactor::CholmodFactor(CholmodFactor&&) noexcept = default;
CholmodFactor& CholmodFactor::operator=(CholmodFactor&&) noexcept = default;

void CholmodFactor::analyze(const Eigen::SparseMatrix<double>& a) {
  if (a.rows() != a.cols()) throw std::invalid_argument("CholmodFactor: matrix must be square");
  if (impl_->factor != nullptr) cholmod_free_factor(&impl_->factor, &impl_->common);
  cholmod_sparse s = Impl::view(a);
  impl_->factor = cholmod_analyze(&s, &impl_->common);
  impl_->ok = false;
  if (impl_->factor == nullptr) {
    throw std::runtime_error("CHOLMOD analyze failed (status " +
                             std::to_string(impl_->common.status) + ")");
  }
}

bool CholmodFactor::factorize(const Eigen::SparseMatrix<double>& a) {
  if (impl_->factor == nullptr) analyze(a);
  cholmod_sparse s = Impl::view(a);
  const int done = cholmod_factorize(&s, impl_->factor, &impl_->common);
  impl_->ok = done != 0 && impl_->common.status == CHOLMOD_OK;
  return impl_->ok;
}

bool CholmodFactor::compute(const Eigen::SparseMatrix<double>& a) {
  analyze(a);
  return factorize(a);
}


void CholmodFactor::solveInPlace(double* b, int columns) {
  if (!impl_->ok) throw std::logic_error("CholmodFactor::solveInPlace without a valid factor");
  const auto n = impl_->factor->n;
  cholmod_dense rhs{};
  rhs.nrow = n;
  rhs.ncol = static_cast<std::size_t>(columns);
  rhs.nzmax = n * rhs.ncol;
  rhs.d = n;
  rhs.x = b;
  rhs.xtype = CHOLMOD_REAL;
  rhs.dtype = CHOLMOD_DOUBLE;
  if (!cholmod_solve2(CHOLMOD_A, impl_->factor, &rhs, nullptr, &impl_->x, nullptr, &impl_->y,
                      &impl_->e, &impl_->common)) {
    throw std::runtime_error("CHOLMOD solve failed");
  }
  std::memcpy(b, impl_->x->x, sizeof(double) * rhs.nzmax);
}

double CholmodFactor::factorNonZeros() const {
  return impl_->factor == nullptr ? 0.0 : impl_->common.lnz;
}

LowerFactor CholmodFactor::exportLower() {
  if (!impl_->ok) throw std::logic_error("CholmodFactor::exportLower without a valid factor");
  cholmod_factor* f = impl_->factor;
  // Simplicial, L L^T, packed, columns in order: plain CSC with the diagonal first per column.
  if (!cholmod_change_factor(CHOLMOD_REAL, 1, 0, 1, 1, f, &impl_->common)) {
    throw std::runtime_error("CHOLMOD change_factor failed");
  }
  const int n = static_cast<int>(f->n);
  const int* p = static_cast<const int*>(f->p);
  const int* rows = static_cast<const int*>(f->i);
  const double* values = static_cast<const double*>(f->x);
  const int* perm = static_cast<const int*>(f->Perm);

  LowerFactor out;
  out.size = n;
  out.permutation.assign(perm, perm + n);
  out.inv_diagonal.resize(n);
  out.col_start.assign(n + 1, 0);
  for (int j = 0; j < n; ++j) {
    if (p[j + 1] <= p[j] || rows[p[j]] != j) {
      throw std::logic_error("CHOLMOD factor column " + std::to_string(j) +
                             " does not start at its diagonal");
    }
    out.inv_diagonal[j] = 1.0 / values[p[j]];
    out.col_start[j + 1] = out.col_start[j] + (p[j + 1] - p[j] - 1);
  }
  out.col_row.resize(out.col_start[n]);
  out.col_value.resize(out.col_start[n]);
  std::vector<std::pair<int, double>> column;
  for (int j = 0; j < n; ++j) {
    column.clear();
    for (int k = p[j] + 1; k < p[j + 1]; ++k) column.emplace_back(rows[k], values[k]);
    std::sort(column.begin(), column.end());  // CHOLMOD does not promise sorted rows
    for (std::size_t k = 0; k < column.size(); ++k) {
      out.col_row[out.col_start[j] + k] = column[k].first;
      out.col_value[out.col_start[j] + k] = column[k].second;
    }
  }
  return out;  // the CHOLMOD copy stays valid for solveInPlace
}

}  // namespace cloth_sim
