/* The exact law of a cell (law/condensed.hpp) for the user material (dualcell_umat.c), callable
 * from C. The law comes from a text file (law/cell_text.hpp) that `dualcell-export --format umat
 * --form cell` writes: dualcell-cell-<id>.txt, in the folder $DUALCELL_CELL_DIR or else the
 * working directory. It is read once per process; each thread has its own evaluator.
 *
 * State variables of a material point (all 0 for the unloaded cell, as the codes start them):
 *   1: the number of broken pairs;  2 … 1 + P: 1 where pair k is broken (P pairs), 2 where it
 *   breaks at the start of the next increment (`between` only: it was at its strength when this
 *   one ended);
 *   then m + n entries: the active set of the last evaluation (−1 lower, 0 free, 1 upper), the
 *   warm start of the next (m = 3 macro stresses, n interface rows); a cell with the shears
 *   along the fibres then the active set of its shear rows (r entries, docs/method.md §16a).
 */
#ifndef DUALCELL_CELL_UMAT_H
#define DUALCELL_CELL_UMAT_H

#ifdef __cplusplus
extern "C" {
#endif

/* The number of state variables law `id` needs, or −1 when its file cannot be read (the reason
 * on stderr, once). */
int dualcell_cell_statev(int id);

/* The law `id` at the in-plane strain e = (ε11, ε22, γ12) from the state `statev` (nstatv
 * entries), which is updated: with between = 0 the debond cascade of the point at e (bonds break
 * within 1e-7 of their strength and never heal); with between = 1 the bonds of the state held (a
 * row at its strength carries its strength: a response continuous in e, on which a Newton
 * method without a line search converges), the pairs the cascade at e would break marked to
 * break at the start of the next increment. An increment repeated at the same load is then one
 * round of a structure's debond loop (dualcell-structure's: equilibrium with the bonds held,
 * then each point's cascade at its strain). `hash`: the card's constants 6 and 7, the file's hash
 * (FNV-1a of its text, high and low 32 bits); a file whose hash differs was replaced after the
 * card was written and is refused. Writes σ = (σ11, σ22, σ12), the tangent D = dσ/dε row by row
 * and the strain energy per unit volume W. Returns 0, or 1 when the file cannot be read or is
 * not the card's, the state is too short, the cell's QP fails, the answer is not finite or
 * anything else fails (memory included: nothing is thrown into the caller); the reason on
 * stderr, once per law and kind. */
int dualcell_cell_law(int id, const double hash[2], const double e[3], double* statev, int nstatv, double s[3],
                      double D[9], double* W, int between);

/* Whether law `id` is the whole ply's (its cell carries the strain and the shears along the
 * fibres: dualcell_cell_law6); 0 when it is in-plane only, −1 when its file cannot be read. */
int dualcell_cell_is_ply(int id);

/* The whole ply's law `id` (a cell with the strain and the shears along the fibres) at the 3D
 * strain e = (ε11, ε22, ε33, γ12, γ13, γ23), Abaqus's order with engineering shears, the
 * material axes 1 = x, 2 = y in the plane of the cells and 3 = z along the fibres, and the
 * temperature change delta_T from the stress-free state (0: none; otherwise the cell must carry
 * it, docs/theory/model.md §1a: e is then the total strain, thermal part included); as
 * dualcell_cell_law otherwise. Writes σ = (σ11, σ22, σ33, σ12, σ13, σ23), the 6 × 6 tangent
 * D = dσ/dε row by row (symmetric) and W. */
int dualcell_cell_law6(int id, const double hash[2], const double e[6], double delta_T, double* statev, int nstatv,
                       double s[6], double D[36], double* W, int between);

/* A card the user material refuses before any law is evaluated (too few constants, an unknown
 * layout, too few state variables): `message` on stderr once per process and message, as every
 * other refusal is told, so that the smaller increment the umat then asks for is never silent. */
void dualcell_umat_refuse(const char* message);

#ifdef __cplusplus
}
#endif

#endif
