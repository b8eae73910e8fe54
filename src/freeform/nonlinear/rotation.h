// Rotations of the nonlinear model: the rotation-vector form of a quaternion and back (the
// guidance field blends rotation vectors), and the rotation nearest to a matrix.
#pragma once

#include "freeform/mesh/types.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace freeform {

// axis * angle with angle in [0, pi], and its inverse.
Vec3 rotation_vector(const Eigen::Quaterniond& q);
Eigen::Quaterniond rotation_from_vector(const Vec3& w);

// The rotation R maximizing trace(R^T a) (the polar factor of a; for a = sum w e' e^T the
// best fit of rest edges e to deformed edges e'), refined in place from the warm start q:
// Newton steps on the rotation near the maximum (2-3 from a warm start, also where a is of
// rank 2: a flat patch), Mueller et al. 2016's gradient steps far from it ("A robust method
// to extract the rotational part of deformations"). Always a unit quaternion, no SVD.
// Returns the iterations taken (max_iterations: not converged to 1e-13 rad).
int extract_rotation(const Eigen::Matrix3d& a, Eigen::Quaterniond& q, int max_iterations = 20);

// How well a determines the rotation q fitted to it: the smallest eigenvalue of the fit's
// Hessian (tr(S) I - sym(S), S = R^T a) over its trace, in [0, 1/3]. 1/3 for edges spanning all
// three directions evenly, 1/4 for a flat, even fan (the turn about its normal is held by both
// in-plane directions), 0 for edges along one line (the turn about it is free); 0 where the
// trace is not positive (q is not a maximum).
double fit_conditioning(const Eigen::Matrix3d& a, const Eigen::Quaterniond& q);

}  // namespace freeform
