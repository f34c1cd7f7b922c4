# Scenes, the host simulator, the paper's examples, pictures and the solver benchmark.
# Included by the top-level Makefile with `include examples/sim.mk` placed after its own
# rules (it uses CC, STRICT, LIBFLAGS, CFLAGS, LDLIBS, BUILD, EDMI_REAL, HOST and the
# $(HOST) directory rule).
#
#   make sim            build $(HOST)/edmi-sim and $(HOST)/test_scene (also part of `make all`)
#   make test-scene     the scene parser's error cases, the shipped scenes, the energy balance
#   make run-examples   the paper's three examples with every scheme: one table (about 31 s on
#                       2 cores); SIM_FULL=1 adds the ten-body tol_Q study (6 more long runs)
#   make plots          CSV traces into $(BUILD)/plots, PNGs into examples/figures (gnuplot);
#                       SIM_FULL=1 adds the ten-body tol_Q study figure
#   make bench          tests/bench/bench_solver.c with 128 bodies and 8192 links: cost vs links
#                       (wall time), then tests/bench/bench_cost.sh: callgrind instructions per
#                       step, per correction and per link, and against velocity Verlet
#   make bench-profile  where a step's instructions go: phases and functions, callgrind
#   make guard-cost     the passivity guard's host cost, callgrind (tests/bench/guard_cost.c)
#   make orbits         does the guard steer conservative orbits? tests/bench/orbits.c in both
#                       precisions: PM with and without its guard, MP and LG on circular LJ
#                       and gravity orbits, drifts of H, J and r against a long-double truth;
#                       one markdown table (about 30 s on one core)
#   make study          what accuracy costs in time (tests/bench/study/): every scheme, velocity
#                       Verlet, semi-implicit Euler and GSL's rk2imp, rk4imp and rk4 on five
#                       scenes; errors against a converged reference, callgrind instructions,
#                       wall time; tables into tests/bench/study/RESULTS.md, figures
#                       examples/figures/study_*.png. STUDY_QUICK=1: the CI subset (two
#                       scenes, three dt's; its tables and figures stay in build/study-quick/)
#   make haptic         examples/haptic.c, the 1 kHz virtual coupling: its table, the CSV
#                       $(BUILD)/plots/haptic.csv and examples/figures/haptic_energy.png
#                       (gnuplot); `make plots` draws the same figure
#
# The simulator sources live in examples/sim/ so that the top-level wildcard over
# examples/*.c (one program per file) does not pick them up.

SIM_SRC := examples/sim
SIM_BIN := $(HOST)/edmi-sim
SIM_TEST := $(HOST)/test_scene
SIM_SCENES := $(wildcard examples/scenes/*.scene)
# Runs in parallel for run-examples and plots: every core (2 on the CI machine).
SIM_JOBS ?= $(shell getconf _NPROCESSORS_ONLN 2>/dev/null || echo 2)
SIM_FULL ?= 0
SIM_PLOTS := $(BUILD)/plots
SIM_FIGURES := examples/figures
SIM_BENCH := $(BUILD)/bench-$(EDMI_REAL)
SIM_BENCH_CAP := -DEDMI_MAX_BODIES=128 -DEDMI_MAX_LINKS=8192
# edmi-sim links its own copy of the library, optimised further: with -ffp-contract=off and
# no fast-math, -O3 gives bit-identical traces to -O2 (checked on all shipped scenes) and
# runs the ten-body scene about 30% faster. `make SIM_OPT=` uses CFLAGS alone.
SIM_OPT ?= -O3
# edmi-sim, its scene parser and its tests take coupled masses (`mass A B m`) up to two bodies
# apart, 128 walls and 128 links (16 balls in a box: 96 walls, 120 pairs): every object of theirs is built with the same
# capacity.
SIM_CAP := -DEDMI_MAX_MASS_GAP=2 -DEDMI_MAX_WALLS=128 -DEDMI_MAX_LINKS=128

.PHONY: sim test-scene run-examples plots bench bench-profile guard-cost orbits haptic haptic-wall study

all: $(SIM_BIN) $(SIM_TEST)
sim: $(SIM_BIN) $(SIM_TEST)

$(HOST)/sim_scene.o: $(SIM_SRC)/scene.c $(SIM_SRC)/scene.h edmi.h | $(HOST)
	$(CC) $(STRICT) $(CFLAGS) -DEDMI_REAL=$(EDMI_REAL) $(SIM_CAP) -I. -c $< -o $@

$(HOST)/sim_edmi.o: edmi.c edmi.h | $(HOST)
	$(CC) $(LIBFLAGS) $(CFLAGS) $(SIM_OPT) -DEDMI_REAL=$(EDMI_REAL) $(SIM_CAP) -c $< -o $@

# edmi-sim checks H of every stored state with tests/lib/passive.c (the soak's check, independent
# of the library's arithmetic) for its "H steps" line and --h-check: in double-word arithmetic
# where its error bound decides, in tp_q (__float128) where it does not.
SIM_PASSIVE := tests/lib/passive.c tests/lib/passive.h
$(SIM_BIN): $(SIM_SRC)/edmi_sim.c $(SIM_SRC)/scene.h $(HOST)/sim_scene.o $(HOST)/sim_edmi.o \
		$(SIM_PASSIVE) edmi.h | $(HOST)
	$(CC) $(STRICT) $(CFLAGS) $(SIM_OPT) -DEDMI_REAL=$(EDMI_REAL) $(SIM_CAP) -I. -Itests/lib $< tests/lib/passive.c \
	    $(HOST)/sim_scene.o $(HOST)/sim_edmi.o -o $@ $(LDLIBS)

$(SIM_TEST): $(SIM_SRC)/test_scene.c $(SIM_SRC)/scene.h $(HOST)/sim_scene.o $(HOST)/sim_edmi.o edmi.h | $(HOST)
	$(CC) $(STRICT) $(CFLAGS) -DEDMI_REAL=$(EDMI_REAL) $(SIM_CAP) -I. $< $(HOST)/sim_scene.o \
	    $(HOST)/sim_edmi.o -o $@ $(LDLIBS)

# edmi-sim --ref's tests (examples/sim/test_ref.sh) and its summary's (test_summary.sh), with a
# double and a float edmi-sim built here for them whatever EDMI_REAL is, --emit-c's
# (examples/sim/test_emit.sh), and the double-word H check's decisions against __float128's
# (examples/sim/test_hcheck.c), both precisions.
SIM_REF_BINS := $(BUILD)/simref/double/edmi-sim $(BUILD)/simref/float/edmi-sim \
                $(BUILD)/simref/double/test_hcheck $(BUILD)/simref/float/test_hcheck
$(BUILD)/simref/%/edmi-sim: $(SIM_SRC)/edmi_sim.c $(SIM_SRC)/scene.c $(SIM_SRC)/scene.h \
		$(SIM_PASSIVE) edmi.c edmi.h
	mkdir -p $(@D)
	$(CC) $(STRICT) $(CFLAGS) -DEDMI_REAL=$* $(SIM_CAP) -I. -Itests/lib $(SIM_SRC)/edmi_sim.c $(SIM_SRC)/scene.c \
	    tests/lib/passive.c edmi.c \
	    -o $@ $(LDLIBS)
$(BUILD)/simref/%/test_hcheck: $(SIM_SRC)/test_hcheck.c $(SIM_SRC)/scene.c $(SIM_SRC)/scene.h \
		$(SIM_PASSIVE) edmi.c edmi.h
	mkdir -p $(@D)
	$(CC) $(STRICT) $(CFLAGS) -DEDMI_REAL=$* $(SIM_CAP) -I. -Itests/lib $(SIM_SRC)/test_hcheck.c $(SIM_SRC)/scene.c \
	    tests/lib/passive.c edmi.c -o $@ $(LDLIBS)
SIM_REF_TESTS := $(foreach r,double float,'$(BUILD)/simref/$(r)/test_hcheck examples/scenes') \
                 $(foreach r,double float,'bash $(SIM_SRC)/test_ref.sh $(BUILD)/simref/$(r)/edmi-sim examples/scenes $(r)') \
                 $(foreach r,double float,'bash $(SIM_SRC)/test_summary.sh $(BUILD)/simref/$(r)/edmi-sim examples/scenes $(r)') \
                 'bash $(SIM_SRC)/test_emit.sh $(BUILD)/simref/double/edmi-sim "$(CC)"'

# Last line: "N passed, N failed" (tests/scripts/run_all.sh can take "$(SIM_TEST) $(SIM_SCENES)").
test-scene: $(SIM_TEST)
	$(SIM_TEST) $(SIM_SCENES)

run-examples: $(SIM_BIN)
	SIM_FULL=$(SIM_FULL) bash examples/run_examples.sh $(SIM_BIN) $(SIM_JOBS)

plots: $(SIM_BIN) $(HOST)/haptic
	SIM_FULL=$(SIM_FULL) HAPTIC=$(HOST)/haptic HAPTIC_REAL=$(EDMI_REAL) \
	    bash examples/plots/make_plots.sh $(SIM_BIN) $(SIM_PLOTS) $(SIM_FIGURES) $(SIM_JOBS)

# The haptic example shares its trajectory with tests/bench/haptic_target.c.
$(HOST)/haptic: examples/haptic_hand.h

haptic: $(HOST)/haptic
	@mkdir -p $(SIM_PLOTS) $(SIM_FIGURES)
	$(HOST)/haptic --csv $(SIM_PLOTS)/haptic.csv
	@if command -v gnuplot >/dev/null 2>&1; then \
	    gnuplot -e "data='$(SIM_PLOTS)'; out='$(SIM_FIGURES)/haptic_energy.png'; prec='$(EDMI_REAL)'" \
	        examples/plots/haptic.gp && echo "  $(SIM_FIGURES)/haptic_energy.png"; \
	else \
	    echo "make haptic: gnuplot not found: skipped $(SIM_FIGURES)/haptic_energy.png (the trace is $(SIM_PLOTS)/haptic.csv)"; \
	fi

# A hand pressing a tool into a wall through the coupling (examples/tool_on_wall.c), then a
# device touching a wall at 1 kHz (examples/haptic_wall.c): the library with walls, its own
# object; the tables, and the passivity map's figure where gnuplot is installed.
$(HOST)/wall/edmi.o: edmi.c edmi.h
	@mkdir -p $(@D)
	$(CC) $(LIBFLAGS) $(CFLAGS) -DEDMI_REAL=$(EDMI_REAL) -DEDMI_MAX_WALLS=1 -c $< -o $@
$(HOST)/wall/haptic_wall: examples/haptic_wall.c $(HOST)/wall/edmi.o edmi.h
	$(CC) $(STRICT) $(CFLAGS) -DEDMI_REAL=$(EDMI_REAL) -DEDMI_MAX_WALLS=1 -I. $< \
	    $(HOST)/wall/edmi.o -o $@ $(LDLIBS)

$(HOST)/wall/tool_on_wall: examples/tool_on_wall.c examples/haptic_hand.h $(HOST)/wall/edmi.o edmi.h
	$(CC) $(STRICT) $(CFLAGS) -DEDMI_REAL=$(EDMI_REAL) -DEDMI_MAX_WALLS=1 -I. $< \
	    $(HOST)/wall/edmi.o -o $@ $(LDLIBS)

haptic-wall: $(HOST)/wall/haptic_wall $(HOST)/wall/tool_on_wall
	@mkdir -p $(SIM_PLOTS) $(SIM_FIGURES)
	$(HOST)/wall/tool_on_wall
	@echo
	$(HOST)/wall/haptic_wall --csv $(SIM_PLOTS)/haptic_wall.csv
	@if command -v gnuplot >/dev/null 2>&1; then \
	    gnuplot -e "data='$(SIM_PLOTS)'; out='$(SIM_FIGURES)/haptic_wall.png'" \
	        examples/plots/haptic_wall.gp && echo "  $(SIM_FIGURES)/haptic_wall.png"; \
	else \
	    echo "make haptic-wall: gnuplot not found: skipped $(SIM_FIGURES)/haptic_wall.png (the table is $(SIM_PLOTS)/haptic_wall.csv)"; \
	fi

# The benchmark needs large capacities in the library and the program alike.
$(SIM_BENCH):
	mkdir -p $@
$(SIM_BENCH)/edmi.o: edmi.c edmi.h | $(SIM_BENCH)
	$(CC) $(LIBFLAGS) $(CFLAGS) -DEDMI_REAL=$(EDMI_REAL) $(SIM_BENCH_CAP) -c $< -o $@
$(SIM_BENCH)/bench_solver: tests/bench/bench_solver.c $(SIM_BENCH)/edmi.o edmi.h
	$(CC) $(STRICT) $(CFLAGS) -DEDMI_REAL=$(EDMI_REAL) $(SIM_BENCH_CAP) -I. $< $(SIM_BENCH)/edmi.o -o $@ $(LDLIBS)

# The callgrind cost table (tests/bench/bench_cost.sh): both precisions, -O2, the same
# capacities, each case a separate run of tests/bench/bench_cost.c.
BC_DIR := $(BUILD)/bench-cost
$(BC_DIR)/bench_cost-%: tests/bench/bench_cost.c tests/lib/bench_scenes.h edmi.c edmi.h
	mkdir -p $(@D)
	$(CC) $(STRICT) -O2 -g -DEDMI_REAL=$* $(SIM_BENCH_CAP) -I. -Itests/lib tests/bench/bench_cost.c edmi.c -o $@ $(LDLIBS)

bench: $(SIM_BENCH)/bench_solver $(BC_DIR)/bench_cost-float $(BC_DIR)/bench_cost-double
	$(SIM_BENCH)/bench_solver
	@sh tests/bench/bench_cost.sh $(BC_DIR)

# Where a step's instructions go: phases and functions per step (tests/bench/bench_profile.sh).
bench-profile: $(BC_DIR)/bench_cost-float $(BC_DIR)/bench_cost-double
	@sh tests/bench/bench_profile.sh $(BC_DIR)

# The passivity guard's cost on the host: callgrind instructions per step (tests/bench/guard_cost.c).
GC_DIR := $(BUILD)/guard-cost
$(GC_DIR)/guard_cost-%: tests/bench/guard_cost.c edmi.c edmi.h
	mkdir -p $(@D)
	$(CC) $(STRICT) -O2 -g -fno-ipa-icf -DEDMI_REAL=$* -I. tests/bench/guard_cost.c edmi.c -o $@ $(LDLIBS)

guard-cost: $(GC_DIR)/guard_cost-float $(GC_DIR)/guard_cost-double
	@for r in float double; do \
	    valgrind --tool=callgrind --callgrind-out-file=$(GC_DIR)/cg-$$r.out $(GC_DIR)/guard_cost-$$r \
	        > $(GC_DIR)/out-$$r.txt 2>/dev/null || exit 1; \
	    callgrind_annotate --inclusive=yes --threshold=100 $(GC_DIR)/cg-$$r.out 2>/dev/null | \
	    awk -v r=$$r '/guard_cost.c:gc_pm_guard_on /{on=$$1} /guard_cost.c:gc_pm_guard_off /{off=$$1} \
	        /guard_cost.c:gc_verlet /{vv=$$1} /guard_cost.c:gc_rest_origin /{ro=$$1} \
	        /guard_cost.c:gc_rest_off /{rf=$$1} END {gsub(",","",on); gsub(",","",off); gsub(",","",vv); \
	        gsub(",","",ro); gsub(",","",rf); \
	        printf "%-6s PM guard on %7.0f, guard off %7.0f, velocity Verlet %4.0f instructions/step; on/off %.2f; share %.1f %%\n", \
	        r, on/2000, off/2000, vv/2000, on/off, 100*(on-off)/on; \
	        printf "%-6s at rest (PM + damper, guard on): anchor at the origin %7.0f, at (0.25, -1, 3) %7.0f instructions/step\n", \
	        r, ro/2000, rf/2000}'; \
	done

# The guard on conservative orbits (tests/bench/orbits.c): both precisions at -O2 against edmi.c,
# one table (the float rows, then the double rows).
ORB_DIR := $(BUILD)/orbits
$(ORB_DIR)/orbits-%: tests/bench/orbits.c edmi.c edmi.h
	mkdir -p $(@D)
	$(CC) $(STRICT) -O2 -DEDMI_REAL=$* -I. tests/bench/orbits.c edmi.c -o $@ $(LDLIBS)

orbits: $(ORB_DIR)/orbits-float $(ORB_DIR)/orbits-double
	$(ORB_DIR)/orbits-float
	$(ORB_DIR)/orbits-double --no-header

# ---- the work-precision study (tests/bench/study/) ----------------------------------------------
# GSL (Debian: libgsl-dev) for its odeiv2 steppers and the reference; valgrind; gnuplot.
STUDY := $(BUILD)/study
STUDY_SRC := tests/bench/study/study.c $(SIM_SRC)/scene.c edmi.c
STUDY_QUICK ?= 0
$(STUDY)/study-double: $(STUDY_SRC) $(SIM_SRC)/scene.h edmi.h
	mkdir -p $(@D)
	$(CC) $(STRICT) $(CFLAGS) -DEDMI_REAL=double -DSTUDY_GSL -I. -I$(SIM_SRC) $(STUDY_SRC) \
	    -o $@ -lgsl -lgslcblas $(LDLIBS)
$(STUDY)/study-float: $(STUDY_SRC) $(SIM_SRC)/scene.h edmi.h
	mkdir -p $(@D)
	$(CC) $(STRICT) $(CFLAGS) -DEDMI_REAL=float -I. -I$(SIM_SRC) $(STUDY_SRC) -o $@ $(LDLIBS)

STUDY_OUT := $(STUDY)$(if $(filter 1,$(STUDY_QUICK)),-quick)
study: $(STUDY)/study-double $(STUDY)/study-float
	mkdir -p $(STUDY_OUT)
	$(MAKE) --no-print-directory study-target > $(STUDY_OUT)/m4f.log 2>&1 || \
	    { cat $(STUDY_OUT)/m4f.log; exit 1; }
	STUDY_QUICK=$(STUDY_QUICK) bash tests/bench/study/run_study.sh $^ $(STUDY_OUT) \
	    $(if $(filter 1,$(STUDY_QUICK)),$(STUDY_OUT)/figures,$(SIM_FIGURES)) $(SIM_JOBS)
