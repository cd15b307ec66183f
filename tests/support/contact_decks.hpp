#pragma once
// Deck text for the contact tests: boxes of hexahedra and lattices of SPH particles with their
// parts, written as a user would write them (so the keyword reader is part of what is tested).
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <string>
#include <type_traits>
#include <vector>

#include "spall/core/types.hpp"
#include "unit/keyword_test_decks.hpp"

namespace spall::test_support {

using test::row;

// A value in at most 10 characters (a fixed-format field: a longer text would spill into the next
// field), to as many significant digits (up to 9) as fit.
inline std::string number(double value) {
  for (int digits = 9; digits > 1; --digits) {
    std::string text = fmt::format("{:.{}g}", value, digits);
    if (text.size() <= 10) return text;
  }
  return fmt::format("{:.1e}", value);
}

// A *NODE coordinate in its 16-character field.
inline std::string coordinate(double value) { return fmt::format("{:.9g}", value); }

// A structured mesh of n[0] x n[1] x n[2] hexahedra of part `pid` (*NODE and *ELEMENT_SOLID): the
// lattice point (i, j, k) at place(i, j, k), nodes numbered from first_node in lattice order and
// elements from first_element. The bottom layer's node IDs (k = 0) go to `bottom` when given.
// `pid` may instead be a function of the element's place (i, j, k) giving its part.
template <class Part, class Place>
std::string hex_lattice(Part pid, std::array<int, 3> n, Id first_node, Id first_element, Place&& place,
                        std::vector<Id>* bottom = nullptr) {
  const auto part_of = [&](int i, int j, int k) -> Id {
    if constexpr (std::is_invocable_v<Part, int, int, int>)
      return pid(i, j, k);
    else
      return pid;
  };
  const auto id = [&](int i, int j, int k) { return first_node + i + (n[0] + 1) * (j + (n[1] + 1) * k); };
  std::string deck = "*NODE\n";
  for (int k = 0; k <= n[2]; ++k)
    for (int j = 0; j <= n[1]; ++j)
      for (int i = 0; i <= n[0]; ++i) {
        const Vec3 x = place(i, j, k);
        deck += row({std::to_string(id(i, j, k)), coordinate(x.x()), coordinate(x.y()), coordinate(x.z())},
                    {8, 16, 16, 16});
        if (k == 0 && bottom) bottom->push_back(id(i, j, k));
      }
  deck += "*ELEMENT_SOLID\n";
  Id eid = first_element;
  for (int k = 0; k < n[2]; ++k)
    for (int j = 0; j < n[1]; ++j)
      for (int i = 0; i < n[0]; ++i) {
        const auto node = [&](int a, int b, int c) { return std::to_string(id(i + a, j + b, k + c)); };
        deck += row({std::to_string(eid++), std::to_string(part_of(i, j, k)), node(0, 0, 0), node(1, 0, 0),
                     node(1, 1, 0), node(0, 1, 0), node(0, 0, 1), node(1, 0, 1), node(1, 1, 1), node(0, 1, 1)},
                    {8, 8, 8, 8, 8, 8, 8, 8, 8, 8});
      }
  return deck;
}

// A box [lower, lower + size] of n[0] x n[1] x n[2] hexahedra (`pid` as in hex_lattice).
template <class Part = Id>
std::string hex_box(Part pid, const Vec3& lower, const Vec3& size, std::array<int, 3> n, Id first_node,
                    Id first_element, std::vector<Id>* bottom = nullptr) {
  return hex_lattice(pid, n, first_node, first_element, [&](int i, int j, int k) {
    return Vec3(lower + Vec3(size.x() * i / n[0], size.y() * j / n[1], size.z() * k / n[2]));
  }, bottom);
}

// A cylinder of radius r and height `height` standing on `base` along z, of n x n hexahedra across
// (a square grid mapped onto the disc by (u, v) -> r (u sqrt(1 - v^2 / 2), v sqrt(1 - u^2 / 2)))
// and `layers` layers; the bottom nodes' IDs go to `bottom` when given.
inline std::string hex_cylinder(Id pid, const Vec3& base, Real radius, Real height, int n, int layers, Id first_node,
                                Id first_element, std::vector<Id>* bottom = nullptr) {
  return hex_lattice(pid, {n, n, layers}, first_node, first_element, [&](int i, int j, int k) {
    const Real u = 2.0 * i / n - 1, v = 2.0 * j / n - 1;
    return Vec3(base + Vec3(radius * u * std::sqrt(1 - v * v / 2), radius * v * std::sqrt(1 - u * u / 2),
                            height * k / layers));
  }, bottom);
}

// A ball of radius r about `centre` of n x n x n hexahedra (n even) as a cubed sphere: the lattice
// point p of the cube [-1, 1]^3 on the cube shell max|p_d| = s goes to the sphere of radius s r,
// along the direction of (tan(pi/4 p_d / s))_d (equiangular: the surface nodes evenly spaced in
// angle on each face, 2 pi r / (4 n) apart along its middle lines).
inline std::string hex_ball(Id pid, const Vec3& centre, Real r, int n, Id first_node, Id first_element) {
  return hex_lattice(pid, {n, n, n}, first_node, first_element, [&](int i, int j, int k) {
    const Vec3 p(2.0 * i / n - 1, 2.0 * j / n - 1, 2.0 * k / n - 1);
    const Real shell = p.cwiseAbs().maxCoeff();
    if (shell == 0) return centre;
    Vec3 direction;
    for (int d = 0; d < 3; ++d) direction[d] = std::tan(std::numbers::pi / 4 * p[d] / shell);
    return Vec3(centre + shell * r * direction.normalized());
  });
}

// *SET_NODE_LIST `sid` of the given nodes, eight to a line.
inline std::string node_set(Id sid, const std::vector<Id>& nodes) {
  std::string deck = "*SET_NODE_LIST\n" + row({std::to_string(sid)});
  for (std::size_t k = 0; k < nodes.size(); k += 8) {
    std::string line;
    for (std::size_t m = k; m < std::min(nodes.size(), k + 8); ++m) line += fmt::format("{:>10}", nodes[m]);
    deck += line + "\n";
  }
  return deck;
}

// SPH particles of part `pid` on the lattice lower + spacing (i, j, k), i < n[0] ..., each of mass
// density x spacing^3, nodes numbered from first_node (*NODE and *ELEMENT_SPH).
inline std::string sph_lattice(Id pid, const Vec3& lower, Real spacing, std::array<int, 3> n, Real density,
                               Id first_node) {
  std::string nodes = "*NODE\n", particles = "*ELEMENT_SPH\n";
  const std::string mass = number(density * spacing * spacing * spacing);
  Id id = first_node;
  for (int k = 0; k < n[2]; ++k)
    for (int j = 0; j < n[1]; ++j)
      for (int i = 0; i < n[0]; ++i, ++id) {
        const Vec3 x = lower + spacing * Vec3(i, j, k);
        nodes += row({std::to_string(id), coordinate(x.x()), coordinate(x.y()), coordinate(x.z())}, {8, 16, 16, 16});
        particles += row({std::to_string(id), std::to_string(pid), mass}, {8, 8, 16});
      }
  return nodes + particles;
}

// How a deformable body is discretized.
enum class Body { fem, spg, sph };

inline const char* body_name(Body b) { return b == Body::fem ? "FEM" : b == Body::spg ? "SPG" : "SPH"; }

// *PART `pid` with its section (same ID) for the body kind, and an elastic material (same ID).
inline std::string deformable_part(Body kind, Id pid, Real density, Real young, Real poisson) {
  const std::string id = std::to_string(pid);
  std::string deck = "*PART\nbody " + id + "\n" + row({id, id, id});
  switch (kind) {
    case Body::fem: deck += "*SECTION_SOLID\n" + row({id, "1"}); break;  // one-point hexahedra, IHQ 0 -> 2
    case Body::spg:
      // IDAM 1 with FS 10: no elastic body's bonds fail.
      deck += "*SECTION_SOLID_SPG\n" + row({id, "47", "0"}) + row({"1.5", "1.5", "1.5", "0", "1", "", "15"}) +
              row({"1", "10.0"});
      break;
    case Body::sph: deck += "*SECTION_SPH\n" + row({id, "1.2"}); break;
  }
  return deck + "*MAT_ELASTIC\n" + row({id, number(density), number(young), number(poisson)});
}

// *PART `pid` of *MAT_RIGID (any solid section sets only its geometry); `fixed` holds all six
// degrees of freedom (CMO 1, CON1 7, CON2 7).
inline std::string rigid_part(Id pid, Real density, Real young, Real poisson, bool fixed) {
  const std::string id = std::to_string(pid);
  return "*PART\nrigid " + id + "\n" + row({id, id, id}) + "*SECTION_SOLID\n" + row({id, "1"}) + "*MAT_RIGID\n" +
         row({id, number(density), number(young), number(poisson)}) +
         (fixed ? row({"1.0", "7", "7"}) : row({"0.0", "0", "0"}));
}

// *PART `pid` of *MAT_RIGID meshed with shells: *SECTION_SHELL (same ID) of thickness t and mass per
// area marea; `fixed` holds all six degrees of freedom.
inline std::string rigid_shell_part(Id pid, Real density, Real young, Real poisson, Real thickness, bool fixed,
                                    Real marea = 0) {
  const std::string id = std::to_string(pid);
  return "*PART\nrigid shells " + id + "\n" + row({id, id, id}) + "*SECTION_SHELL\n" + row({id, "2"}) +
         row({number(thickness), "", "", "", "", number(marea)}) + "*MAT_RIGID\n" +
         row({id, number(density), number(young), number(poisson)}) +
         (fixed ? row({"1.0", "7", "7"}) : row({"0.0", "0", "0"}));
}

// A rectangle [lower, lower + a e1 + b e2] of n[0] x n[1] quadrilateral shells of part `pid`
// (*NODE and *ELEMENT_SHELL), N1 N2 N3 N4 counter-clockwise about e1 x e2: the shells' normal.
inline std::string shell_rectangle(Id pid, const Vec3& lower, const Vec3& e1, const Vec3& e2, std::array<int, 2> n,
                                   Id first_node, Id first_element) {
  const auto id = [&](int i, int j) { return first_node + i + (n[0] + 1) * j; };
  std::string deck = "*NODE\n";
  for (int j = 0; j <= n[1]; ++j)
    for (int i = 0; i <= n[0]; ++i) {
      const Vec3 x = lower + (Real(i) / n[0]) * e1 + (Real(j) / n[1]) * e2;
      deck += row({std::to_string(id(i, j)), coordinate(x.x()), coordinate(x.y()), coordinate(x.z())}, {8, 16, 16, 16});
    }
  deck += "*ELEMENT_SHELL\n";
  Id eid = first_element;
  for (int j = 0; j < n[1]; ++j)
    for (int i = 0; i < n[0]; ++i)
      deck += row({std::to_string(eid++), std::to_string(pid), std::to_string(id(i, j)), std::to_string(id(i + 1, j)),
                   std::to_string(id(i + 1, j + 1)), std::to_string(id(i, j + 1))},
                  {8, 8, 8, 8, 8, 8});
  return deck;
}

}  // namespace spall::test_support
