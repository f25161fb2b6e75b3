// Basic numeric types shared by every part of consph. They live in Utilities/, the bottom
// layer, so that utilities (meshes, point files, solvers) need nothing from Simulation/;
// Simulation/Common.h includes this header for everything above.
#pragma once
#include <Eigen/Core>
#include <cstdint>

namespace consph {

#if CONSPH_USE_DOUBLE
using Real = double;
#else
using Real = float;
#endif

// DontAlign: fields are std::vector<Vector3r> that map 1:1 onto a NumPy (N, 3) array.
using Vector3r = Eigen::Matrix<Real, 3, 1, Eigen::DontAlign>;
using Matrix3r = Eigen::Matrix<Real, 3, 3, Eigen::DontAlign>;
using Quaternionr = Eigen::Quaternion<Real, Eigen::DontAlign>;
using Index = std::uint32_t;

inline constexpr const char* precisionName() { return sizeof(Real) == 8 ? "double" : "float"; }

}  // namespace consph
