#pragma once
// The macro state of a cell or a ply: the one value every layer passes, from a scene's paths and
// a points file to the exact law and the umat (docs/architecture.md, "One macro state").
//
// Its components, in the law's order (engineering shears):
//
//   k       xx   yy   xy    zz    xz    yz    dT
//   value   σ̄ or ε̄ (xx, yy, xy)  ε33   γxz   γyz   ΔT
//
// The in-plane components are each a stress or a strain (stress_driven); along the fibres the
// strain ε33 and the shears Γ = (γxz, γyz) are given and σ33, ⟨τ⟩ are the response (the work
// per unit volume is σ̄·ε̄ + σ33 ε33 + τ·Γ, docs/theory/model.md §3a, §3b). ΔT, the temperature
// change from the stress-free state, has no work pair; nothing carries it yet (issue 55 is where
// it comes in). Along a path the components that grow with the load factor t (scaled: the
// in-plane ones, by default) are t·value, the others are held at their value:
//
//   x_k = t·value_k  (k scaled),   x_k = value_k  (k held).
//
// Adding a component is one enumerator here and its physics where it enters
// (docs/architecture.md lists the files); every layer in between passes the state on.
#include <Eigen/Core>
#include <cstdint>

namespace dualcell {

struct MacroState {
  enum Component : int { xx, yy, xy, zz, xz, yz, dT, count };
  using Vector = Eigen::Matrix<double, count, 1>;
  using Mask = std::uint8_t;  // bit k: component k
  static constexpr Mask in_plane_mask = 0b0000111;
  static constexpr Mask along_mask = 1 << zz;
  static constexpr Mask shear_mask = (1 << xz) | (1 << yz);
  static constexpr Mask temperature_mask = 1 << dT;

  Vector value = Vector::Zero();
  Mask stress_driven = 0;       // bit k: value_k is a stress (else a strain; for dT, a temperature)
  Mask scaled = in_plane_mask;  // bit k: x_k = t·value_k (else held at value_k)
  double factor = 1;            // t

  // The in-plane macro stress σ̄ (tensor order xx, yy, xy as the solver's), or the in-plane strain
  // ε̄ (engineering shear), at load factor t; nothing held.
  static MacroState stress(const Eigen::Vector3d& sigma, double t = 1) {
    MacroState s;
    s.value.head<3>() = sigma;
    s.stress_driven = in_plane_mask;
    s.factor = t;
    return s;
  }
  static MacroState strain(const Eigen::Vector3d& e, double t = 1) {
    MacroState s;
    s.value.head<3>() = e;
    s.factor = t;
    return s;
  }
  // The whole ply's six strains e = (εxx, εyy, γxy, ε33, γxz, γyz), the law's order: the in-plane
  // part at load factor 1, the rest held.
  static MacroState ply_strain(const Eigen::Matrix<double, 6, 1>& e) {
    MacroState s = strain(e.head<3>());
    s.hold(zz, e(3)).hold(xz, e(4)).hold(yz, e(5));
    return s;
  }
  // Holds a strain along the fibres, the shears along them, or a temperature change: given, not
  // scaled by the load factor.
  MacroState& hold(Component k, double v) {
    value(k) = v;
    scaled &= static_cast<Mask>(~(1 << k));
    stress_driven &= static_cast<Mask>(~(1 << k));
    return *this;
  }
  MacroState& hold_shear(const Eigen::Vector2d& gamma) { return hold(xz, gamma(0)).hold(yz, gamma(1)); }
  // The same state at another load factor.
  MacroState at_factor(double t) const {
    MacroState s = *this;
    s.factor = t;
    return s;
  }

  // The applied value x_k.
  double operator()(Component k) const { return (scaled >> k & 1) ? factor * value(k) : value(k); }
  Eigen::Vector3d in_plane() const { return {(*this)(xx), (*this)(yy), (*this)(xy)}; }
  double eps33() const { return (*this)(zz); }
  Eigen::Vector2d gamma() const { return {(*this)(xz), (*this)(yz)}; }
  double delta_T() const { return (*this)(dT); }
  bool in_plane_stress() const { return (stress_driven & in_plane_mask) == in_plane_mask; }
  bool in_plane_strain() const { return (stress_driven & in_plane_mask) == 0; }
  // The components whose applied value is not 0.
  Mask nonzero() const {
    Mask m = 0;
    for (int k = 0; k < count; ++k)
      if ((*this)(static_cast<Component>(k)) != 0) m |= static_cast<Mask>(1 << k);
    return m;
  }
  // Whether anything beyond the plane is given (a strain or shears along the fibres, ΔT).
  bool beyond_plane() const { return (nonzero() & ~in_plane_mask) != 0; }
};

}  // namespace dualcell
