#pragma once
// The MLP's building blocks on a batch, each forward beside its VJP. Activations are
// column-major [features, n] (one column per sample), weights column-major [out, in], so a
// layer is one GEMM Y = W·X whose operands are contiguous. A layer whose input is a
// concatenation [A; B] (the skip connection, the colour layer) splits W = [W_A | W_B] by
// columns and runs two GEMMs instead of copying the concatenation.
//
// VJPs accumulate (+=) into every v_ output; callers zero them. Eigen's `noalias() =`
// product zeroes the destination and accumulates anyway, so += costs nothing extra.
//
// Eigen::Ref binds to Maps and column blocks without copying (inner stride 1); callers
// pass only such views, never expressions, so no temporary is allocated.
#include <algorithm>
#include <cmath>

#include "splat/core/activations.hpp"
#include "splat/nerf/eigen_core.hpp"

namespace splat::nerf_detail {

template <typename Scalar>
using Matrix = Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic>;  // column-major
template <typename Scalar>
using Vector = Eigen::Matrix<Scalar, Eigen::Dynamic, 1>;
template <typename Scalar>
using MatrixRef = Eigen::Ref<Matrix<Scalar>>;
template <typename Scalar>
using ConstMatrixRef = Eigen::Ref<const Matrix<Scalar>>;
template <typename Scalar>
using VectorRef = Eigen::Ref<Vector<Scalar>>;
template <typename Scalar>
using ConstVectorRef = Eigen::Ref<const Vector<Scalar>>;

// After the GEMM: Y += b, then optionally ReLU, in one pass over Y (memory, not
// arithmetic, is what a second pass would cost).
enum class Activation { kNone, kRelu };

template <typename Scalar>
void add_bias_activate(ConstVectorRef<Scalar> b, Activation activation, MatrixRef<Scalar> y) {
  if (activation == Activation::kRelu)
    y = (y.colwise() + b).cwiseMax(Scalar(0));
  else
    y.colwise() += b;
}

// v_b += v_Y·1, one column after another. Not Eigen's rowwise().sum(): it pairs columns for
// its vector lanes but not for the rows it peels off to align the destination, so the
// rounding of each row would depend on where the buffer happens to sit in memory (and with
// it on the allocator's history); here every row is summed in column order.
template <typename Scalar>
void add_row_sums(ConstMatrixRef<Scalar> v_y, VectorRef<Scalar> v_b) {
  for (Eigen::Index j = 0; j < v_y.cols(); ++j) v_b += v_y.col(j);
}

// ---- Affine layer: Y = act(W·X + b) ----------------------------------------------------

template <typename Scalar>
void dense_forward(ConstMatrixRef<Scalar> w, ConstVectorRef<Scalar> b, ConstMatrixRef<Scalar> x,
                   Activation activation, MatrixRef<Scalar> y) {
  y.noalias() = w * x;
  add_bias_activate<Scalar>(b, activation, y);
}

// Z = W·X + b, given v_Z (the cotangent before the activation: relu_vjp_inplace first):
//   v_W += v_Z·Xᵀ,  v_b += v_Z·1 (row sums),  v_X += Wᵀ·v_Z.   (Here v_y names v_Z.)
// `v_x` may be null (input needs no gradient, e.g. the encoding in training).
template <typename Scalar>
void dense_vjp(ConstMatrixRef<Scalar> w, ConstMatrixRef<Scalar> x, ConstMatrixRef<Scalar> v_y,
               MatrixRef<Scalar> v_w, VectorRef<Scalar> v_b, MatrixRef<Scalar>* v_x) {
  v_w.noalias() += v_y * x.transpose();
  add_row_sums<Scalar>(v_y, v_b);
  if (v_x) v_x->noalias() += w.transpose() * v_y;
}

// ---- On a concatenation: Y = act([W_A | W_B]·[A; B] + b) = act(W_A·A + W_B·B + b) -------

template <typename Scalar>
void dense2_forward(ConstMatrixRef<Scalar> w, ConstVectorRef<Scalar> b, ConstMatrixRef<Scalar> a,
                    ConstMatrixRef<Scalar> second, Activation activation, MatrixRef<Scalar> y) {
  y.noalias() = w.leftCols(a.rows()) * a;
  y.noalias() += w.rightCols(second.rows()) * second;
  add_bias_activate<Scalar>(b, activation, y);
}

// The VJP of each half is dense_vjp's with the matching column block of W (and of v_W):
//   v_W_A += v_Y·Aᵀ, v_W_B += v_Y·Bᵀ, v_A += W_Aᵀ·v_Y, v_B += W_Bᵀ·v_Y, v_b += v_Y·1.
template <typename Scalar>
void dense2_vjp(ConstMatrixRef<Scalar> w, ConstMatrixRef<Scalar> a, ConstMatrixRef<Scalar> second,
                ConstMatrixRef<Scalar> v_y, MatrixRef<Scalar> v_w, VectorRef<Scalar> v_b,
                MatrixRef<Scalar>* v_a, MatrixRef<Scalar>* v_second) {
  const Eigen::Index na = a.rows(), nb = second.rows();
  v_w.leftCols(na).noalias() += v_y * a.transpose();
  v_w.rightCols(nb).noalias() += v_y * second.transpose();
  add_row_sums<Scalar>(v_y, v_b);
  if (v_a) v_a->noalias() += w.leftCols(na).transpose() * v_y;
  if (v_second) v_second->noalias() += w.rightCols(nb).transpose() * v_y;
}

// ---- ReLU (forward fused into add_bias_activate) ------------------------------------------

// h = max(z, 0):  v_z = v_h·[z > 0]. The mask is read from the output (h > 0 ⇔ z > 0), so
// backward needs only the stored activations. In place: v_h becomes v_z.
template <typename Scalar>
void relu_vjp_inplace(ConstMatrixRef<Scalar> h, MatrixRef<Scalar> v) {
  v = (h.array() > Scalar(0)).select(v, Scalar(0));
}

// ---- Scalar activations of the heads ----------------------------------------------------

// softplus(z) = log(1 + eᶻ), written max(z, 0) + log1p(e^{−|z|}) so eᶻ never overflows.
template <typename Scalar>
Scalar softplus(Scalar z) {
  return std::max(z, Scalar(0)) + std::log1p(std::exp(-std::abs(z)));
}

// d softplus/dz = eᶻ/(1 + eᶻ) = sigmoid(z).
template <typename Scalar>
Scalar softplus_vjp(Scalar z, Scalar v_out) {
  return v_out / (Scalar(1) + std::exp(-z));
}

template <typename Scalar>
Scalar relu(Scalar z) {
  return std::max(z, Scalar(0));
}

template <typename Scalar>
Scalar relu_vjp(Scalar z, Scalar v_out) {
  return z > Scalar(0) ? v_out : Scalar(0);
}

// s = sigmoid(z) (splat/core/activations.hpp):  ds/dz = s(1 − s), from the stored output.
template <typename Scalar>
Scalar sigmoid_vjp_from_output(Scalar s, Scalar v_out) {
  return v_out * s * (Scalar(1) - s);
}

}  // namespace splat::nerf_detail
