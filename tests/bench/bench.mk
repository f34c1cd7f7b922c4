# tests/bench/bench.mk: the host benchmarks, the work-precision study and issue 21's hard cases.
# Included by the top-level Makefile after examples/sim.mk (it uses CC, STRICT, LIBFLAGS,
# CFLAGS, LDLIBS, BUILD, EDMI_REAL, and sim.mk's SIM_SRC, SIM_FIGURES and SIM_JOBS: the study
# reads scenes with the simulator's parser, examples/sim/scene.c, and draws its figures into
# examples/figures/ beside the other figures README and docs show). The target benchmarks
# (bench-target, worst-target, haptic-target, study-target) are in port/target.mk, with the
# board rules they share; their sources are here too.
#
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
#   make hard           issue 21's hard cases (tests/bench/hard/run.sh): four measurement
#                       programs, both precisions, three runs each; tables into $(BUILD)/hard

.PHONY: bench bench-profile guard-cost orbits study hard

BENCH_DIR := $(BUILD)/bench-$(EDMI_REAL)
BENCH_CAP := -DEDMI_MAX_BODIES=128 -DEDMI_MAX_LINKS=8192

# The benchmark needs large capacities in the library and the program alike.
$(BENCH_DIR):
	mkdir -p $@
$(BENCH_DIR)/edmi.o: edmi.c edmi.h | $(BENCH_DIR)
	$(CC) $(LIBFLAGS) $(CFLAGS) -DEDMI_REAL=$(EDMI_REAL) $(BENCH_CAP) -c $< -o $@
$(BENCH_DIR)/bench_solver: tests/bench/bench_solver.c $(BENCH_DIR)/edmi.o edmi.h
	$(CC) $(STRICT) $(CFLAGS) -DEDMI_REAL=$(EDMI_REAL) $(BENCH_CAP) -I. $< $(BENCH_DIR)/edmi.o -o $@ $(LDLIBS)

# The callgrind cost table (tests/bench/bench_cost.sh): both precisions, -O2, the same
# capacities, each case a separate run of tests/bench/bench_cost.c.
BC_DIR := $(BUILD)/bench-cost
$(BC_DIR)/bench_cost-%: tests/bench/bench_cost.c tests/lib/bench_scenes.h edmi.c edmi.h
	mkdir -p $(@D)
	$(CC) $(STRICT) -O2 -g -DEDMI_REAL=$* $(BENCH_CAP) -I. -Itests/lib tests/bench/bench_cost.c edmi.c -o $@ $(LDLIBS)

bench: $(BENCH_DIR)/bench_solver $(BC_DIR)/bench_cost-float $(BC_DIR)/bench_cost-double
	$(BENCH_DIR)/bench_solver
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

# Issue 21's hard cases, measured on the current edmi.c (tests/bench/hard/run.sh says what each
# program prints). They measure; nothing here passes or fails but a build or a crash.
hard:
	sh tests/bench/hard/run.sh $(BUILD)/hard
