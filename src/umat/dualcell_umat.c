/* The cell law as an Abaqus-style user material (umat), for CalculiX (materials named
 * ABAQUS...) and other codes with the same interface (docs/method.md §14, §15, §16a;
 * docs/guide/calculix.md): the cone-wise law with the fuse (layout 1), the exact law of the
 * cell (layout 2, cell_umat.h), or the exact law of the whole ply (layout 3: all six components
 * from the cell, nothing filled in).
 *
 * In the plane of the cells (strain ε = (ε11, ε22, γ12), engineering shear) the stress is
 *   σ(ε) = C_c ε + Σ_k β_k ⟨q_k·ε⟩₊ q_k,   tangent C_c + Σ_k β_k H(q_k·ε) q_k q_kᵀ,
 * with the bonded law until the point's stress leaves the onset surface (max_f g_f·σ ≥ 1) and
 * the law past the fuse from then on, for good (state variable 1: 0 bonded, 1 fused; the code
 * keeps it only when the increment converges). Out of the plane the point is decoupled and
 * linear, σ33 = E33 ε33, σ13 = G13 γ13, σ23 = G23 γ23 (the card's: the cell's ply constants
 * where the law carries the whole ply, else the rule of mixtures): plane-strain
 * elements keep ε33 = γ13 = γ23 = 0, where the in-plane law holds exactly.
 *
 * Constants (*USER MATERIAL, CONSTANTS = n, written by dualcell-export --format umat):
 * layout 3 takes a 5th constant: 1 where bonds break between increments (cell_umat.h,
 *   `between`), 0 or absent where the cascade runs within each; and a 6th, the stress-free
 *   temperature T0 of a cell that carries a temperature change (docs/theory/model.md §1a): the
 *   point is evaluated at ΔT = temp + dtemp − T0 with the total strain (no *EXPANSION: the cell
 *   has its own); absent, ΔT = 0.
 * layout 3, the whole ply's exact law (a cell with the strain and the shears along the fibres,
 *   docs/method.md §16a): 1: 3   2: id, the law's file   3–4: its hash; σ and the 6 × 6 tangent
 *   from the cell in the material axes 1 = x, 2 = y (the plane of the cells), 3 = z (the
 *   fibres); the state variables as cell_umat.h says.
 * layout 2, the exact law: 1: 2   2: id, the law's file dualcell-cell-<id>.txt (cell_umat.h)
 *   3–5: E33, G13, G23   6–7: that file's hash (high and low 32 bits; a replaced file is refused);
 *   the state variables as cell_umat.h says (the debond cascade of the material point, kept by
 *   the code for converged increments only).
 * layout 1, the cone-wise law:
 *   1: layout version (1)       2: K_b, planes of the bonded law     3: K_a, planes past the fuse
 *   4: F, onset facets (0: no fuse)   5–7: E33, G13, G23
 *   then the bonded law: C_c row by row (9), then per plane q1, q2, q3, β (4 K_b);
 *   then, when K_a > 0, the law past the fuse the same way (9 + 4 K_a);
 *   then the facets g_f row by row (3 F), in stress (σ11, σ22, σ12).
 * ntens must be 6 (CalculiX passes 6 for every element, 2D ones included).
 */
#include <stddef.h>

#include "cell_umat.h"

enum { max_planes = 32 };

typedef struct {
  const double* C;     /* 3 × 3, row by row */
  const double* q;     /* planes, 4 numbers each: q1, q2, q3, β */
  int planes;
} cone_law;

/* σ = ∂W/∂ε and its tangent at e; returns W. */
static double cone_evaluate(const cone_law* law, const double e[3], double s[3], double D[3][3]) {
  double W = 0;
  for (int i = 0; i < 3; ++i) {
    s[i] = 0;
    for (int j = 0; j < 3; ++j) {
      s[i] += law->C[3 * i + j] * e[j];
      D[i][j] = law->C[3 * i + j];
    }
    W += 0.5 * e[i] * s[i];
  }
  for (int k = 0; k < law->planes; ++k) {
    const double* p = law->q + 4 * k;
    const double opening = p[0] * e[0] + p[1] * e[1] + p[2] * e[2];
    if (opening <= 0) continue;
    for (int i = 0; i < 3; ++i) {
      s[i] += p[3] * opening * p[i];
      for (int j = 0; j < 3; ++j) D[i][j] += p[3] * p[i] * p[j];
    }
    W += 0.5 * p[3] * opening * opening;
  }
  return W;
}

/* The Abaqus umat interface, Fortran calling convention (every argument by reference, the
 * length of cmname last). */
void umat_(double* stress, double* statev, double* ddsdde, double* sse, double* spd, double* scd, double* rpl,
           double* ddsddt, double* drplde, double* drpldt, const double* stran, const double* dstran,
           const double* time, const double* dtime, const double* temp, const double* dtemp, const double* predef,
           const double* dpred, const char* cmname, const int* ndi, const int* nshr, const int* ntens,
           const int* nstatv, const double* props, const int* nprops, const double* coords, const double* drot,
           double* pnewdt, const double* celent, const double* dfgrd0, const double* dfgrd1, const int* noel,
           const int* npt, const int* layer, const int* kspt, const int* kstep, const int* kinc,
           size_t cmname_length) {
  (void)scd, (void)rpl, (void)ddsddt, (void)drplde, (void)drpldt, (void)time, (void)dtime;
  (void)predef, (void)dpred, (void)cmname, (void)ndi, (void)nshr, (void)coords, (void)drot, (void)celent;
  (void)dfgrd0, (void)dfgrd1, (void)noel, (void)npt, (void)layer, (void)kspt, (void)kstep, (void)kinc;
  (void)cmname_length;
  const int n = *ntens;
  double e6[6];
  for (int i = 0; i < 6; ++i) e6[i] = stran[i] + dstran[i];
  const double e[3] = {e6[0], e6[1], e6[3]}; /* ε11, ε22, γ12 */
  double s[3], D[3][3], W, E33, G13, G23;
  if (n == 6 && props[0] == 3) {
    double D36[36];
    const int between = *nprops >= 5 && props[4] != 0;
    /* The temperature change from the stress-free state: the code's temperature at the end of the
     * increment less the card's 6th constant (none: 0). */
    const double delta_T = *nprops >= 6 ? *temp + *dtemp - props[5] : 0;
    if (*nprops < 4) {
      dualcell_umat_refuse("a layout-3 card (the whole ply's exact law) with fewer than 4 constants (3, id and the "
                           "cell file's hash): export the law again");
      *pnewdt = 0.25; /* a smaller increment, failing visibly */
      return;
    }
    if (dualcell_cell_law6((int)props[1], props + 2, e6, delta_T, statev, *nstatv, stress, D36, sse, between) != 0) {
      *pnewdt = 0.25; /* no law or a failed QP (told by the law): a smaller increment, failing visibly */
      return;
    }
    for (int i = 0; i < 36; ++i) ddsdde[i] = D36[i]; /* symmetric: row by row is column by column */
    *spd = 0;
    return;
  }
  if (n == 6 && props[0] == 2) {
    if (*nprops < 7) {
      dualcell_umat_refuse("a layout-2 card (the exact law) with fewer than 7 constants: no cell file's hash (a card "
                           "written before it): export the law again");
      *pnewdt = 0.25; /* refused: a smaller increment, failing visibly */
      return;
    }
    E33 = props[2], G13 = props[3], G23 = props[4];
    double D9[9];
    if (dualcell_cell_law((int)props[1], props + 5, e, statev, *nstatv, s, D9, &W, 0) != 0) {
      *pnewdt = 0.25; /* no law or a failed QP: ask for a smaller increment, which fails visibly */
      return;
    }
    for (int i = 0; i < 9; ++i) D[i / 3][i % 3] = D9[i];
  } else {
    const int Kb = (int)props[1], Ka = (int)props[2], F = (int)props[3];
    const int needed = 7 + 9 + 4 * Kb + (Ka > 0 ? 9 + 4 * Ka : 0) + 3 * F;
    const char* wrong = n != 6 ? "ntens is not 6 (the umat takes the six components CalculiX passes)"
                        : props[0] != 1
                            ? "the card's first constant is not a layout (1 cone-wise, 2 exact law, 3 whole ply)"
                        : Kb < 1 || Kb > max_planes || Ka < 0 || Ka > max_planes || F < 0
                            ? "a layout-1 card whose counts of planes or facets are out of range (K_b in [1, 32], "
                              "K_a in [0, 32], F >= 0)"
                        : *nprops < needed ? "a layout-1 card with fewer constants than its counts need"
                        : *nstatv < 1      ? "a layout-1 card needs 1 state variable (*DEPVAR)"
                                           : NULL;
    if (wrong) {
      dualcell_umat_refuse(wrong);
      *pnewdt = 0.25; /* a wrong card: ask for a smaller increment, which fails the analysis visibly */
      return;
    }
    E33 = props[4], G13 = props[5], G23 = props[6];
    const cone_law bonded = {props + 7, props + 16, Kb};
    const double* after_start = props + 16 + 4 * Kb;
    const cone_law after = {after_start, after_start + 9, Ka};
    const double* facets = after_start + (Ka > 0 ? 9 + 4 * Ka : 0);
    int fused = statev[0] >= 0.5 && Ka > 0;
    W = cone_evaluate(fused ? &after : &bonded, e, s, D);
    if (!fused && Ka > 0 && F > 0) {
      double phi = 0;
      for (int f = 0; f < F; ++f) {
        const double g = facets[3 * f] * s[0] + facets[3 * f + 1] * s[1] + facets[3 * f + 2] * s[2];
        if (g > phi) phi = g;
      }
      if (phi >= 1) {
        fused = 1;
        W = cone_evaluate(&after, e, s, D);
      }
    }
    statev[0] = fused;
  }

  const int in_plane[3] = {0, 1, 3};
  for (int i = 0; i < 36; ++i) ddsdde[i] = 0;
  for (int i = 0; i < 6; ++i) stress[i] = 0;
  for (int i = 0; i < 3; ++i) {
    stress[in_plane[i]] = s[i];
    for (int j = 0; j < 3; ++j) ddsdde[in_plane[i] + 6 * in_plane[j]] = D[i][j];
  }
  stress[2] = E33 * e6[2], stress[4] = G13 * e6[4], stress[5] = G23 * e6[5];
  ddsdde[2 + 6 * 2] = E33, ddsdde[4 + 6 * 4] = G13, ddsdde[5 + 6 * 5] = G23;
  *sse = W + 0.5 * (E33 * e6[2] * e6[2] + G13 * e6[4] * e6[4] + G23 * e6[5] * e6[5]);
  *spd = 0;
}
