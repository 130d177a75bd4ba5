#include "engine/common/sparse_cholesky.hpp"

#ifdef SURFDEFORM_HAVE_CHOLMOD
#include <Eigen/CholmodSupport>
#else
#include <Eigen/SparseCholesky>
#endif

namespace surfdeform {

struct SparseCholesky::Impl {
#ifdef SURFDEFORM_HAVE_CHOLMOD
  Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Lower> factor;
#else
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower> factor;
#endif
};

SparseCholesky::SparseCholesky(const Eigen::SparseMatrix<double>& a)
    : impl_(std::make_unique<Impl>()) {
  impl_->factor.compute(a);
}

SparseCholesky::~SparseCholesky() = default;

bool SparseCholesky::ok() const { return impl_->factor.info() == Eigen::Success; }

Eigen::MatrixXd SparseCholesky::Solve(const Eigen::MatrixXd& b) const {
  return impl_->factor.solve(b);
}

const char* SparseCholesky::Backend() {
#ifdef SURFDEFORM_HAVE_CHOLMOD
  return "cholmod";
#else
  return "eigen";
#endif
}

}  // namespace surfdeform
