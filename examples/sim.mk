# Scenes, the host simulator, the paper's examples and pictures (the benchmarks and the study:
# tests/bench/bench.mk).
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
# edmi-sim links its own copy of the library, optimised further: with -ffp-contract=off and
# no fast-math, -O3 gives bit-identical traces to -O2 (checked on all shipped scenes) and
# runs the ten-body scene about 30% faster. `make SIM_OPT=` uses CFLAGS alone.
SIM_OPT ?= -O3
# edmi-sim, its scene parser and its tests take coupled masses (`mass A B m`) up to two bodies
# apart, 128 walls and 128 links (16 balls in a box: 96 walls, 120 pairs): every object of theirs is built with the same
# capacity.
SIM_CAP := -DEDMI_MAX_MASS_GAP=2 -DEDMI_MAX_WALLS=128 -DEDMI_MAX_LINKS=128

.PHONY: sim test-scene run-examples plots haptic haptic-wall

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
