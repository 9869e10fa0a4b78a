#pragma once
// Distinct multi-indices of symmetric 3D tensors of order n <= kMaxHermiteOrder ([Seiler14 §4.1]).
// A symmetric tensor of order n has (n+1)(n+2)/2 distinct components; component alpha = (a_x, a_y, a_z)
// with a_x + a_y + a_z = n stands for the n!/alpha! index tuples that are permutations of it.
#include <array>
#include <vector>

namespace deformation_enrichment::hermite {

/// Highest order supported by the basis (the paper uses N <= 3; N = 4 is the headroom the issue asks for).
inline constexpr int kMaxHermiteOrder = 4;

/// Exponents (a_x, a_y, a_z) of one distinct component.
using MultiIndex = std::array<int, 3>;

/// Number of distinct components of a symmetric order-n tensor: (n+1)(n+2)/2.
int numComponents(int order);

/// Distinct multi-indices of order n in lexicographic order of their sorted index tuples
/// (n=1: x y z; n=2: xx xy xz yy yz zz; n=3: xxx xxy xxz xyy xyz xzz yyy yyz yzz zzz).
/// Throws InvalidInputError for n outside [0, kMaxHermiteOrder].
const std::vector<MultiIndex>& multiIndices(int order);

/// Multiplicity n!/(a_x! a_y! a_z!): how many full-tensor index tuples share this component.
double multiplicity(const MultiIndex& alpha);

/// Position of alpha in multiIndices(a_x + a_y + a_z).
int componentIndex(const MultiIndex& alpha);

/// n! as a double (n <= 20).
double factorial(int n);

}  // namespace deformation_enrichment::hermite
