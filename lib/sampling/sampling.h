#pragma once
// Deterministic samples of approach directions (S^2) and orientations (SO(3)), any count.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <vector>

namespace cdbench {

// Spherical Fibonacci lattice: z_k = 1 - (2k + 1)/n, azimuth k x golden angle. Low discrepancy.
std::vector<Eigen::Vector3d> sphere_fibonacci(std::size_t n);

// Regular latitude-longitude grid: rows at polar angles (i + 1/2) pi / rows, points spread evenly
// in azimuth within a row, rows holding counts proportional to sin(polar angle); exactly n points.
std::vector<Eigen::Vector3d> sphere_grid(std::size_t n);

// Super-Fibonacci spirals (Alexa, CVPR 2022): n unit quaternions spread uniformly over SO(3).
std::vector<Eigen::Quaterniond> rotations_super_fibonacci(std::size_t n);

// Uniform random rotations (Shoemake), from a seed; the same on every platform (mt19937_64 and
// our own conversion to doubles, not the library's unspecified distributions).
std::vector<Eigen::Quaterniond> rotations_random(std::size_t n, std::uint64_t seed);

// By the names of the command-line options: directions "fibonacci" or "grid", orientations
// "super-fibonacci" or "random" (seeded). InputError naming the option for any other name;
// check_sampling_names checks the names alone (before any work).
void check_sampling_names(const std::string& directions, const std::string& orientations);
std::vector<Eigen::Vector3d> sample_directions(const std::string& kind, std::size_t n);
std::vector<Eigen::Quaterniond> sample_orientations(const std::string& kind, std::size_t n, std::uint64_t seed);

}  // namespace cdbench
