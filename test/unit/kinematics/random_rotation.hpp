#pragma once
// A rotation drawn from std::rand under `seed`, the same on every machine with the same C library.
#include <Eigen/Geometry>
#include <cstdlib>

inline Eigen::Matrix3d randomRotation(unsigned seed) {
  std::srand(seed);
  return Eigen::Quaterniond(Eigen::Vector4d::Random()).normalized().toRotationMatrix();
}
