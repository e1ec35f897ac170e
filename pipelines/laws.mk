# The laws of the pipelines' cells, the ply's constants and the small cell: included by the
# Makefile at this place (its variables, $(BIN), $(TOOLS), $(SCENES), $(OUT_ROOT), ... defined
# before), kept apart because these studies are one idea, the compact and exact laws' checks.
# ---- the laws of the pipelines' cells and their self-checks ------------------------------
# Each scene's exact law (the cell condensed onto its interface rows), its replay of the sweep
# it came from, and the compact cone-wise law against it over ~1000 directions (with adhesion
# also past the fuse, ~280 directions each through its cascade).
LAW_SCENES ?= default bimodular glass-epoxy-vf50 structure-cell-contact structure-cell-adhesion \
  periodic-glass-epoxy periodic-carbon-epoxy offcentre rve4-adhesion
LAWS_OUT := $(OUT_ROOT)/laws

laws: $(LAWS_OUT)/table.md

# ---- the ply's nine constants (docs/method.md §3a, §3b, §3c) -------------------------------
# The bonded cells' engineering constants for a 3D model (fibres along z, the ply's axis 1):
# seven dualcell-solve runs per cell (unit in-plane stresses, e33 and both together, the
# longitudinal shear), on the laws' meshes; each cell's CalculiX card (<cell>.inp) checked by
# CalculiX on a cube, and the cell itself in CalculiX as a periodic 3D slab (tools/ccx_ply.py). Seconds.
PLY_SCENES ?= default structure-cell-adhesion rve4-adhesion
PLY_OUT := $(OUT_ROOT)/ply

ply: $(PLY_OUT)/constants.md $(PLY_OUT)/states.md $(PLY_OUT)/laminate/laminate.md $(PLY_OUT)/umat/cube.md \
  $(PLY_OUT)/umat/cube_small.md $(PLY_OUT)/shear.md $(PLY_OUT)/small.md $(PLY_OUT)/umat/beam.md \
  $(PLY_OUT)/umat/beam-fuse.md

$(PLY_OUT)/constants.md: $(foreach s,$(PLY_SCENES),$(LAWS_OUT)/$(s)/law.h5) $(TOOLS)/ply_constants.py $(TOOLS)/ccx_ply.py
	@mkdir -p $(dir $@)
	$(PY) $(TOOLS)/ply_constants.py $(BIN) $@ $(foreach s,$(PLY_SCENES),$(SCENES)/$(s).toml:$(LAWS_OUT)/$(s)/mesh.h5) \
	  --ccx ccx

# The whole ply's exact law in CalculiX (the umat's layout 3, docs/method.md §16a): the ply
# scene (the default cell with [load] macro = "full") swept and fitted like the laws above, its
# card and cell file, and one C3D8 under the six unit load cases, random states and states past
# the bonds' strength against dualcell-law --full (tools/ccx_umat_check.py cube). Needs ccx-umat.
$(PLY_OUT)/umat/ply.inp: $(LAWS_OUT)/ply/law.h5 $(BUILT)
	@mkdir -p $(dir $@)
	$(BIN)/dualcell-export --quiet --law $< --format umat --form cell --name PLY --out $@

$(PLY_OUT)/umat/cube.md: $(CCX_UMAT) $(PLY_OUT)/umat/ply.inp $(TOOLS)/ccx_umat_check.py
	$(PY) $(TOOLS)/ccx_umat_check.py cube $(CCX_UMAT) $(PLY_OUT)/umat/ply.inp $@ --law $(LAWS_OUT)/ply/law.h5 \
	  --bin $(BIN)

# A beam of 3D elements with the whole ply's exact law (layout 3) in CalculiX against
# dualcell-structure's transverse solution of the same beam (tools/ccx_solid_beam.py): below the
# first break (structure-ply-beam.toml, the card as exported by default), and past it
# (structure-ply-beam-fuse.toml: bonds per point at CalculiX's quadrature points) with the card
# whose bonds break between increments (--breaks between, cell id 3), each load level repeated
# once per debond round of dualcell-structure's. About 2 min of ccx.
$(PLY_OUT)/umat/ply_rounds.inp: $(LAWS_OUT)/ply/law.h5 $(BUILT)
	@mkdir -p $(dir $@)
	$(BIN)/dualcell-export --quiet --law $< --format umat --form cell --breaks between --cell-id 3 --name PLY_ROUNDS \
	  --out $@

$(PLY_OUT)/umat/%.h5: $(SCENES)/structure-ply-%.toml $(LAWS_OUT)/ply/law.h5 $(BUILT)
	@mkdir -p $(dir $@)
	$(BIN)/dualcell-structure --quiet --config $< --law $(LAWS_OUT)/ply/law.h5 --out $@

$(PLY_OUT)/umat/beam.md: $(CCX_UMAT) $(PLY_OUT)/umat/ply.inp $(PLY_OUT)/umat/beam.h5 $(TOOLS)/ccx_solid_beam.py \
    $(TOOLS)/ccx_umat_check.py
	$(PY) $(TOOLS)/ccx_solid_beam.py $(CCX_UMAT) $(PLY_OUT)/umat/ply.inp $(PLY_OUT)/umat/beam.h5 \
	  $(SCENES)/structure-ply-beam.toml $@

$(PLY_OUT)/umat/beam-fuse.md: $(CCX_UMAT) $(PLY_OUT)/umat/ply_rounds.inp $(PLY_OUT)/umat/beam-fuse.h5 \
    $(TOOLS)/ccx_solid_beam.py $(TOOLS)/ccx_umat_check.py
	$(PY) $(TOOLS)/ccx_solid_beam.py $(CCX_UMAT) $(PLY_OUT)/umat/ply_rounds.inp $(PLY_OUT)/umat/beam-fuse.h5 \
	  $(SCENES)/structure-ply-beam-fuse.toml $@

# The small cell of the whole ply (docs/method.md §16e) against its exact law along six-component
# strain paths, with adhesion (the ply scene) and without (bimodular-ply): /law/small_ply_check.
$(PLY_OUT)/small.md: $(LAWS_OUT)/ply/law.h5 $(LAWS_OUT)/bimodular-ply/law.h5 $(TOOLS)/ply_small.py
	@mkdir -p $(dir $@)
	$(PY) $(TOOLS)/ply_small.py $@ $(LAWS_OUT)/ply/law.h5 $(LAWS_OUT)/bimodular-ply/law.h5

# The same with the compact law, the small cell of the whole ply (docs/method.md §16e; its card
# under cell id 2). Its check against the exact law is over --max-law-error (the one fuse stands
# for every partial cascade), so it is written with --force: what is checked here is that the umat
# evaluates the small cell as dualcell-law does, not the small cell's error.
$(PLY_OUT)/umat/ply_small.inp: $(LAWS_OUT)/ply/law.h5 $(BUILT)
	@mkdir -p $(dir $@)
	$(BIN)/dualcell-export --quiet --law $< --format umat --form small --cell-id 2 --force --name PLY_SMALL --out $@

$(PLY_OUT)/umat/cube_small.md: $(CCX_UMAT) $(PLY_OUT)/umat/ply_small.inp $(TOOLS)/ccx_umat_check.py
	$(PY) $(TOOLS)/ccx_umat_check.py cube $(CCX_UMAT) $(PLY_OUT)/umat/ply_small.inp $@ --law $(LAWS_OUT)/ply/law.h5 \
	  --bin $(BIN) --form small

# The shear along the fibres through its debond cascade (docs/method.md §16a): the ply scene's
# exact law against its sweep's one-body checks (/shear_check), path by path, and its picture
# (shear.png: τ along Γ, loaded past the breaks and unloaded). Seconds.
$(PLY_OUT)/shear.md: $(LAWS_OUT)/ply/law.h5 $(TOOLS)/ply_shear.py
	@mkdir -p $(dir $@)
	$(PY) $(TOOLS)/ply_shear.py $(BIN) $< $(LAWS_OUT)/ply/sweep.h5 $@

# How a 3D model uses them: a [0/90]s beam of C3D20R bricks in CalculiX, the plies the default
# cell's bonded card, against laminate theory (tools/ccx_laminate.py), with its picture
# (laminate.png: σxx through the thickness). About 10 s.
$(PLY_OUT)/laminate/laminate.md: $(PLY_OUT)/constants.md $(TOOLS)/ccx_laminate.py
	$(PY) $(TOOLS)/ccx_laminate.py $(PLY_OUT)/constants.csv default $(dir $@) --ccx ccx

# The constants per bond state (bonded, after the fuse, a contact cell's), in tension and in
# compression (tools/ply_states.py, docs/method.md §3c), each state's cards checked by CalculiX;
# states.png shows each row's moduli. The default cell's rows are also the exact law's (the ply
# scene's /law/ply, the same cell with macro = "full"), measured against these solves, and its
# fuse load is the law's.
PLY_STATE_SCENES ?= default rve4-adhesion bimodular

$(PLY_OUT)/states.md: $(foreach s,$(PLY_STATE_SCENES),$(LAWS_OUT)/$(s)/law.h5) $(LAWS_OUT)/ply/law.h5 \
    $(TOOLS)/ply_states.py $(TOOLS)/ply_constants.py
	@mkdir -p $(dir $@)
	$(PY) $(TOOLS)/ply_states.py $(BIN) $@ $(foreach s,$(PLY_STATE_SCENES),$(SCENES)/$(s).toml:$(LAWS_OUT)/$(s)/mesh.h5) \
	  --law default=$(LAWS_OUT)/ply/law.h5 --ccx ccx

# ---- the small cell (src/study/bench_small_cell.cpp, docs/method.md §16c) -------------------
# The compact laws of cells without adhesion against their exact laws, error against the cost of
# an evaluation: the exact law on its own solutions, fitted small cells and the cone-wise law, on
# the pipelines' cells of more than 64 interface rows and a 16-fibre RVE (704); a 64-fibre RVE
# (3 194 constraint rows: above the exact law's reach) whose small cell is fitted to 1 600 sphere
# paths' full solves and measured at the 160 held out (its sweep about 45 min); the 16-fibre
# RVE's small cell in bending beams; the bimodular cell's small cell in CalculiX's beam; the
# default scene's small cell with a fuse (§16d) in a cantilever past the fuse and in one CalculiX
# element. About 75 min. SMALL_CELL_SCENES=rve36-contact adds the 36-fibre RVE (about 1 560 rows: formed, above
# what the fit samples; the benchmark then also measures its small cell against the exact law).
SMALL_CELL_SCENES ?= bimodular offcentre rve16-contact rve64-contact
SMALL_CELL_OUT := $(OUT_ROOT)/small-cell

small-cell: $(SMALL_CELL_OUT)/table.md $(SMALL_CELL_OUT)/ccx/beam-small.md $(SMALL_CELL_OUT)/ccx/element-fuse.md

# The small cell in CalculiX: the bimodular cell's (128 interface rows, so it has one) as the
# umat's cell, on the structures pipeline's bimodular beam (pure bending, H = 4), against
# dualcell-structure --form small on the same mesh.
$(SMALL_CELL_OUT)/ccx/umat.inp: $(LAWS_OUT)/bimodular/law.h5 $(BUILT)
	@mkdir -p $(dir $@)
	$(BIN)/dualcell-export --quiet --law $< --format umat --form small --name BIMODULAR --out $@

$(SMALL_CELL_OUT)/ccx/structure-small.h5: $(STRUCT_OUT)/contact/bending-H4/structure.toml $(LAWS_OUT)/bimodular/law.h5 $(BUILT)
	@mkdir -p $(dir $@)
	$(BIN)/dualcell-structure --quiet --config $< --law $(LAWS_OUT)/bimodular/law.h5 --form small --out $@

$(SMALL_CELL_OUT)/ccx/beam-small.md: $(CCX_UMAT) $(SMALL_CELL_OUT)/ccx/umat.inp $(SMALL_CELL_OUT)/ccx/structure-small.h5 \
    $(STRUCT_OUT)/contact/bending-H4/structure.toml $(TOOLS)/ccx_umat_check.py
	$(PY) $(TOOLS)/ccx_umat_check.py beam $(CCX_UMAT) $(SMALL_CELL_OUT)/ccx/umat.inp \
	  $(SMALL_CELL_OUT)/ccx/structure-small.h5 $(STRUCT_OUT)/contact/bending-H4/structure.toml $@
	@cat $@

# The small cell a law keeps against its exact law at 1 000 random directions, without refitting
# the ladder (tools/small_against_cell.py): for an exact law above the fit's dense check, e.g.
# the 36-fibre RVE's (about 15 min: 1 000 dense QPs of 1 562 rows).
$(SMALL_CELL_OUT)/%/against_cell.md: $(LAWS_OUT)/%/law.h5 $(TOOLS)/small_against_cell.py $(BUILT)
	$(PY) $(TOOLS)/small_against_cell.py $(BIN) $< $@ > /dev/null

$(SMALL_CELL_OUT)/%/small_cell.md: $(LAWS_OUT)/%/law.h5 $(BUILT)
	@mkdir -p $(dir $@)
	$(BIN)/dualcell-bench --out-dir $(dir $@) --small-cell $< > /dev/null

# The RVE's law in bending beams: 8 × 2 cells against its exact law (about 3 min), 128 × 16
# against the cone-wise law's time.
$(SMALL_CELL_OUT)/structure.md: $(LAWS_OUT)/rve16-contact/law.h5 $(TOOLS)/small_cell_structure.py $(BUILT)
	$(PY) $(TOOLS)/small_cell_structure.py $(BIN) $< $(dir $@) > /dev/null

# The default scene's small cell with its fuse as the umat's cell: one element in CalculiX under
# twelve strains below the onset against dualcell-law (bound 1e-6, the printed digits). --force:
# the cell misses the exact law past the fuse by more than the export's 2 % (6.3 %, dualcell-fit's
# summary); below the onset, where the element stays, it is the exact bonded law.
$(SMALL_CELL_OUT)/ccx/fuse/umat.inp: $(LAWS_OUT)/default/law.h5 $(BUILT)
	@mkdir -p $(dir $@)
	$(BIN)/dualcell-export --quiet --law $< --format umat --form small --force --name DEFAULT --out $@

$(SMALL_CELL_OUT)/ccx/element-fuse.md: $(CCX_UMAT) $(SMALL_CELL_OUT)/ccx/fuse/umat.inp $(LAWS_OUT)/default/law.h5 \
    $(TOOLS)/ccx_umat_check.py
	$(PY) $(TOOLS)/ccx_umat_check.py element $(CCX_UMAT) $(SMALL_CELL_OUT)/ccx/fuse/umat.inp $@ \
	  --law $(LAWS_OUT)/default/law.h5 --bin $(BIN)

# The default scene's law (adhesion: its small cell carries the fuse, docs/method.md §16d) in the
# 32 × 4 cantilever loaded past the fuse and unloaded, against its exact law (about 4 min) and its
# cone-wise law, step by step.
$(SMALL_CELL_OUT)/fuse.md: $(LAWS_OUT)/default/law.h5 $(SCENES)/structure-cantilever.toml \
    $(TOOLS)/small_cell_structure.py $(BUILT)
	$(PY) $(TOOLS)/small_cell_structure.py $(BIN) $< $(dir $@) --fuse $(SCENES)/structure-cantilever.toml > /dev/null

$(SMALL_CELL_OUT)/table.md: $(foreach s,$(SMALL_CELL_SCENES),$(SMALL_CELL_OUT)/$(s)/small_cell.md) \
    $(SMALL_CELL_OUT)/structure.md $(SMALL_CELL_OUT)/fuse.md
	cat $^ > $@
	@cat $@
