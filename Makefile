# edmi build. `make help` prints the lines below that start with "#>".
#> edmi: make targets, each with a bound on its wall time from a fresh clone on a quiet 2-core
#> machine (builds included; the measured time rounded up to 5, 10, 20 or 30 s or 1, 2, 3, 5,
#> 10, 15, 20 or 30 min, so a new measurement needs a new quote only when it breaks the bound
#> or falls two steps below it: `bash .ci/run` prints each step's time against it, and STALE
#> there), and the Debian 12 packages each needs beyond make, gcc and bash (`bash .ci/run`
#> installs them all).
#>
#> -- the two commands --
#> make run             ≤ 2 min
#>     the main job: the spring's accuracy table, then the paper's three examples with every
#>     scheme (edmi-sim), a line as each of its 27 runs ends
#> make test            ≤ 10 min  needs g++ (clang: one check more)
#>     the test suite in four configurations (double, float, both under ASan+UBSan) and in
#>     three builds with features compiled out (FEATURES), the simulator's tests, the fuzz
#>     corpus replayed, library checks; last line "N passed, N failed"
#>
#> -- build --
#> make                 ≤ 20 s
#>     edmi.o, the examples and edmi-sim into build/double/ (EDMI_REAL=float: build/float/)
#> make sim             ≤ 10 s
#>     edmi-sim and the scene parser's test program
#> make help            ≤ 5 s
#>     this list
#> make clean           ≤ 20 s
#>     remove build/
#>
#> -- the host: examples and measurements --
#> make run-examples    ≤ 1 min
#>     the paper's three examples alone (the second half of make run)
#> make test-scene      ≤ 10 s
#>     the scene parser's tests
#> make haptic          ≤ 5 s     needs gnuplot for the figure
#>     the 1 kHz virtual coupling (examples/haptic.c): its table and trace, and the figure
#>     where gnuplot is installed
#> make haptic-wall     ≤ 5 s     needs gnuplot for the figure
#>     a hand pressing a tool into a wall through the coupling, each scheme
#>     (examples/tool_on_wall.c); a device touching a wall at 1 kHz (examples/haptic_wall.c):
#>     which device damping keeps the loop passive, the wall explicit or edmi's behind a
#>     virtual coupling; its figure
#> make plots           ≤ 2 min   needs gnuplot for the figures
#>     traces of the paper's examples and every figure in examples/figures/ (without gnuplot:
#>     the traces and the cable's table only)
#> make orbits          ≤ 30 s
#>     does the guard steer conservative orbits? drifts of H, J and r, guarded PM against PM
#>     without it, MP and LG
#> make bench           ≤ 1 min   needs valgrind
#>     cost against scene size (wall time), then callgrind instructions per step and per
#>     correction against velocity Verlet
#> make bench-profile   ≤ 10 s    needs valgrind
#>     where a step's instructions go, by phase and by function
#> make guard-cost      ≤ 20 s    needs valgrind
#>     the passivity guard's cost on the host (callgrind)
#> make study           ≤ 20 min  needs valgrind, libgsl-dev, qemu-system-arm; gnuplot for the figures
#>     what accuracy costs: every scheme and its peers (velocity Verlet, GSL) on five scenes,
#>     error against instructions
#> make study STUDY_QUICK=1 ≤ 1 min
#>     the CI subset: two scenes, three dt's; tables and figures in build/study-quick/
#> make soak            ≤ 10 min
#>     the guard's adversarial scenes, 10^6 steps per case, both precisions (SOAK_STEPS=N for
#>     fewer)
#> make hard            ≤ 3 min
#>     issue 21's hard cases measured (tests/bench/hard/): Lennard-Jones wall, coupled masses with
#>     the fallback, a user spring, a flipping port; both precisions, three runs each, tables
#>     into build/hard/
#> make refs            ≤ 5 s
#>     regenerate tests/ref_track.h, the double reference the float suite tracks, after a
#>     change that moves results
#>
#> -- fuzzing --
#> make fuzz            ≤ 2 min   needs clang, llvm, libclang-rt-14-dev
#>     the API fuzzer, both precisions side by side, FUZZ_TIME seconds each (default 60), then
#>     the coupling build (FEAT_coupling) for a quarter of that
#> make fuzz-cov        ≤ 10 s    needs clang, llvm
#>     edmi.c's line and branch coverage by the fuzz corpora
#>
#> -- microcontrollers: cross builds and QEMU --
#> make cross           ≤ 2 min   needs gcc-arm-none-eabi, libnewlib-arm-none-eabi, gcc-riscv64-unknown-elf
#>     edmi.c for Cortex-M4F, M7, M0+ and rv32imac: size table, capacity table, build
#>     options table (EDMI_WITH_*), external references
#> make test-target     ≤ 5 min   needs gcc-arm-none-eabi, libnewlib-arm-none-eabi, qemu-system-arm
#>     the test suite on QEMU: Cortex-M4F (float; also in the coupling build) and Cortex-M7
#>     (double), with the mass-matrix tests
#> make bench-target    ≤ 2 min   needs gcc-arm-none-eabi, libnewlib-arm-none-eabi, qemu-system-arm
#>     instructions per step, the worst case, stack and the time bound, on QEMU -icount
#> make worst-target    ≤ 1 min   needs gcc-arm-none-eabi, libnewlib-arm-none-eabi, qemu-system-arm
#>     the costliest step of a one-body virtual coupling a search can make on the Cortex-M4F,
#>     and the bound the count of its pieces gives (fails if a step exceeds it)
#> make haptic-target   ≤ 20 s    needs gcc-arm-none-eabi, libnewlib-arm-none-eabi, qemu-system-arm
#>     the 1 kHz virtual coupling on the Cortex-M4F: instructions per tick
#> make smoke-target    ≤ 10 s    needs gcc-arm-none-eabi, libnewlib-arm-none-eabi, qemu-system-arm
#>     the QEMU runner's own exit statuses (pass, failure, fault, hang, stack overflow)
#> make study-target    ≤ 1 min   needs gcc-arm-none-eabi, libnewlib-arm-none-eabi, qemu-system-arm
#>     the study's Cortex-M4F column (make study runs it)
#> make check-ram       ≤ 10 s    needs gcc-arm-none-eabi, gcc-riscv64-unknown-elf
#>     the RAM formula of the sizing table against sizeof
#> make check-sqrt      ≤ 5 s
#>     port/riscv/sqrt.c against the host's libm
#> make check-port      ≤ 10 s    needs gcc-arm-none-eabi, gcc-riscv64-unknown-elf
#>     check-ram and check-sqrt
#> make cmake-check     ≤ 10 s    needs cmake, gcc-arm-none-eabi, libnewlib-arm-none-eabi, qemu-system-arm
#>     the CMake target edmi in a consumer project, for the host and the Cortex-M4F (run on
#>     QEMU)
#>
#> Override on the command line: make CC=clang CFLAGS='-O3' EDMI_REAL=float BUILD=out

CC ?= cc
CXX ?= g++
NM ?= nm
EDMI_REAL ?= double
BUILD ?= build
CFLAGS ?= -O2 -g
LDLIBS ?= -lm

# Always on, whatever CFLAGS says. -ffp-contract=off: no FMA contraction, so results are
# bit-reproducible across compilers and targets. -fno-math-errno: the sqrt builtin is one
# instruction. No -ffast-math anywhere.
STRICT := -std=c99 -Wall -Wextra -Wpedantic -Wshadow -Wdouble-promotion -Wconversion \
          -ffp-contract=off -fno-math-errno
# The library itself must be warnings-clean; tests and examples only have to build.
LIBFLAGS := $(STRICT) -Werror
SAN := -fsanitize=address,undefined -fno-sanitize-recover=all -O1

ARM_CC ?= arm-none-eabi-gcc
ARM_NM ?= arm-none-eabi-nm
ARM_SIZE ?= arm-none-eabi-size
ARM_TARGET := -mcpu=cortex-m4 -mthumb -mfpu=fpv4-sp-d16 -mfloat-abi=hard

.PHONY: all run test soak refs cross clean fuzz fuzz-cov help

# ---- host: library and examples ------------------------------------------------------------
HOST := $(BUILD)/$(EDMI_REAL)
EXAMPLES := $(patsubst examples/%.c,$(HOST)/%,$(wildcard examples/*.c))

all: $(HOST)/edmi.o $(EXAMPLES)

# Scenes, edmi-sim, the paper's examples, plots (examples/sim.mk); the host benchmarks, the
# study and the hard cases (tests/bench/bench.mk, which uses sim.mk's names).
include examples/sim.mk
include tests/bench/bench.mk

$(HOST)/edmi.o: edmi.c edmi.h | $(HOST)
	$(CC) $(LIBFLAGS) $(CFLAGS) -DEDMI_REAL=$(EDMI_REAL) -c edmi.c -o $@

$(HOST)/%: examples/%.c $(HOST)/edmi.o edmi.h | $(HOST)
	$(CC) $(STRICT) $(CFLAGS) -DEDMI_REAL=$(EDMI_REAL) -I. $< $(HOST)/edmi.o -o $@ $(LDLIBS)

# The main job: the spring's accuracy table, then the paper's three examples (edmi-sim). Its
# two programs build side by side (SIM_JOBS at a time) unless make was given its own -j.
run:
	$(MAKE) --no-print-directory $(if $(filter -j%,$(MAKEFLAGS)),,-j$(SIM_JOBS)) \
	    $(HOST)/paper_spring $(SIM_BIN)
	$(HOST)/paper_spring
	$(MAKE) --no-print-directory run-examples

# ---- tests: the same sources in four configurations ------------------------------------------
# The suites (tests/test_*.c) with the helpers shared by tests, benchmarks, port checks and the
# simulator (tests/lib/, included by bare name: TEST_INC). test_obj names an object by its
# source's base name, whichever of the two folders holds it.
TEST_SRC := $(wildcard tests/test_*.c) tests/lib/harness.c tests/lib/host_io.c tests/lib/scenes.c \
            tests/lib/passive.c
TEST_HDR := $(wildcard tests/*.h tests/lib/*.h)
TEST_INC := -I. -Itests/lib
test_obj = $(addprefix $(1)/,$(notdir $(patsubst %.c,%.o,$(2))))
CONFIGS := double float double-san float-san
real_of = $(firstword $(subst -, ,$(1)))
# The suites run with walls compiled in (EDMI_MAX_WALLS, 0 by default), as edmi-sim and the
# fuzzer, and with room for 16 balls in a box (tests/test_contact.c: 64 walls, 120 contacts).
TEST_CAP := -DEDMI_MAX_WALLS=64 -DEDMI_MAX_LINKS=128
flags_of = $(CFLAGS) $(TEST_CAP) $(if $(findstring -san,$(1)),$(SAN))

# $(1) = configuration: objects and the binary $(BUILD)/test-$(1)/edmi_tests
define test_config
$(BUILD)/test-$(1)/edmi.o: edmi.c edmi.h | $(BUILD)/test-$(1)
	$$(CC) $$(LIBFLAGS) $(call flags_of,$(1)) -DEDMI_REAL=$(call real_of,$(1)) -c $$< -o $$@
$(BUILD)/test-$(1)/%.o: tests/%.c edmi.h $$(TEST_HDR) | $(BUILD)/test-$(1)
	$$(CC) $$(STRICT) $(call flags_of,$(1)) $$(TEST_INC) -DEDMI_REAL=$(call real_of,$(1)) -c $$< -o $$@
$(BUILD)/test-$(1)/%.o: tests/lib/%.c edmi.h $$(TEST_HDR) | $(BUILD)/test-$(1)
	$$(CC) $$(STRICT) $(call flags_of,$(1)) $$(TEST_INC) -DEDMI_REAL=$(call real_of,$(1)) -c $$< -o $$@
$(BUILD)/test-$(1)/edmi_tests: $(BUILD)/test-$(1)/edmi.o \
		$(call test_obj,$(BUILD)/test-$(1),$(TEST_SRC))
	$$(CC) $(call flags_of,$(1)) $$^ -o $$@ $$(LDLIBS)
endef
$(foreach c,$(CONFIGS),$(eval $(call test_config,$(c))))

# Builds with features compiled out (edmi.h, EDMI_WITH_*): the same suite in both precisions,
# skipping the cases that need what is out (tests/lib/harness.h, th_skip). `make cross` prints
# their flash (port/target.mk). decaying: the energy-safe schemes GE, PM, PT; coupling: one PM
# virtual coupling (PM, harmonic links, anchors and moving anchors, the guard); conservative:
# MP and LG without the guard.
FEAT_decaying := -DEDMI_WITH_MP=0 -DEDMI_WITH_LG=0
FEAT_coupling := -DEDMI_WITH_MP=0 -DEDMI_WITH_LG=0 -DEDMI_WITH_GE=0 -DEDMI_WITH_PT=0 \
    -DEDMI_WITH_QUARTIC=0 -DEDMI_WITH_NEO_HOOKE=0 -DEDMI_WITH_LJ=0 -DEDMI_WITH_INVERSE=0 \
    -DEDMI_WITH_USER=0 -DEDMI_WITH_CONTACT=0 -DEDMI_WITH_FIELD=0 -DEDMI_WITH_PORTS=0 \
    -DEDMI_WITH_SCENE=0 -DEDMI_MAX_DAMPERS=0
FEAT_conservative := -DEDMI_WITH_GE=0 -DEDMI_WITH_PM=0 -DEDMI_WITH_PT=0 -DEDMI_WITH_GUARD=0
FEATURES := decaying coupling conservative
FEAT_BINS := $(foreach f,$(FEATURES),$(foreach r,double float,$(BUILD)/feat-$(f)-$(r)/edmi_tests))
$(BUILD)/feat-%/edmi_tests: $(TEST_SRC) $(TEST_HDR) edmi.c edmi.h
	mkdir -p $(@D)
	$(CC) $(LIBFLAGS) $(CFLAGS) -DEDMI_REAL=$(word 2,$(subst -, ,$*)) \
	    $(FEAT_$(word 1,$(subst -, ,$*))) -c edmi.c -o $(@D)/edmi.o
	$(CC) $(STRICT) $(CFLAGS) -DEDMI_REAL=$(word 2,$(subst -, ,$*)) \
	    $(FEAT_$(word 1,$(subst -, ,$*))) $(TEST_INC) $(TEST_SRC) $(@D)/edmi.o -o $@ $(LDLIBS)

# Library checks: freestanding -Werror build in both precisions, symbol prefix and external
# references (tests/scripts/check_lib.sh), and the header used from C++ (tests/programs/cxx_header.cpp).
CHECK := $(BUILD)/check
$(CHECK)/edmi-%.o: edmi.c edmi.h | $(CHECK)
	$(CC) $(LIBFLAGS) -ffreestanding $(CFLAGS) -DEDMI_REAL=$* -c $< -o $@
$(CHECK)/cxx_header-%.o: tests/programs/cxx_header.cpp edmi.h | $(CHECK)
	$(CXX) -std=c++11 -Wall -Wextra -Werror -DEDMI_REAL=$* -I. -c $< -o $@
$(CHECK)/cxx_header-%: $(CHECK)/cxx_header-%.o $(CHECK)/edmi-%.o
	$(CXX) $^ -o $@
.SECONDARY: $(CHECK)/cxx_header-double.o $(CHECK)/cxx_header-float.o

TEST_BINS := $(foreach c,$(CONFIGS),$(BUILD)/test-$(c)/edmi_tests)
# The fuzz harness over its seed corpus and reproducers, under ASan+UBSan (see "fuzz" below).
REPLAY_BINS := $(BUILD)/replay-double/replay $(BUILD)/replay-float/replay
CXX_BINS := $(CHECK)/cxx_header-double $(CHECK)/cxx_header-float
CHECK_OBJS := $(CHECK)/edmi-double.o $(CHECK)/edmi-float.o \
              $(BUILD)/test-double/edmi.o $(BUILD)/test-float/edmi.o

# The Newton matrix stored as a band (EDMI_MAX_MATRIX) against the dense store, bit for bit
# (tests/programs/band_store.c): 64 bodies, the band of a 63-body chain, under ASan+UBSan.
BAND_CFG_dense := -DEDMI_MAX_BODIES=64 -DEDMI_MAX_LINKS=128
BAND_CFG_narrow := $(BAND_CFG_dense) -DEDMI_MAX_MATRIX=3024 -DBAND_NARROW
BAND_BINS := $(foreach r,double float,$(foreach v,dense narrow,$(BUILD)/band-$(r)-$(v)/band_store))
$(BUILD)/band-%/band_store: tests/programs/band_store.c edmi.c edmi.h
	mkdir -p $(@D)
	$(CC) $(LIBFLAGS) -O1 -g -fsanitize=address,undefined -fno-sanitize-recover=all \
	    -DEDMI_REAL=$(word 1,$(subst -, ,$*)) $(BAND_CFG_$(word 2,$(subst -, ,$*))) -I. \
	    tests/programs/band_store.c edmi.c -o $@ $(LDLIBS)
BAND_RUNS := $(foreach r,double float,'bash tests/scripts/band_check.sh $(BUILD)/band-$(r)-dense/band_store \
             $(BUILD)/band-$(r)-narrow/band_store')

# The general mass matrix (tests/programs/mass_matrix.c with the harness and tests/lib/passive.c; also on
# the emulated targets, port/target.mk): EDMI_MAX_MASS_GAP = 1, 8 bodies, the band store of a
# chain (EDMI_MAX_MATRIX = 48 N), both precisions, under ASan+UBSan.
MASS_CFG := -DEDMI_MAX_BODIES=8 -DEDMI_MAX_MATRIX=384 -DEDMI_MAX_MASS_GAP=1
MASS_SRC := tests/programs/mass_matrix.c tests/lib/harness.c tests/lib/passive.c
MASS_BINS := $(BUILD)/mass-double/mass_matrix $(BUILD)/mass-float/mass_matrix
$(BUILD)/mass-%/mass_matrix: $(MASS_SRC) tests/lib/host_io.c tests/lib/harness.h tests/lib/passive.h edmi.c edmi.h
	mkdir -p $(@D)
	$(CC) $(LIBFLAGS) -O1 -g -fsanitize=address,undefined -fno-sanitize-recover=all \
	    -DEDMI_REAL=$* $(MASS_CFG) $(TEST_INC) $(MASS_SRC) tests/lib/host_io.c edmi.c -o $@ $(LDLIBS)

# Consistent mass matrices that are definite but not diagonally dominant (tests/programs/mass_spd.c: a
# triangle and a tetrahedron, every scheme, the guard's tank identity against a __float128
# truth, refusals; also on the emulated targets, port/target.mk): EDMI_MAX_MASS_GAP = 3 over 4
# bodies, so every pair may be coupled (the dense 12 x 12 Newton matrix fits the default
# EDMI_MAX_MATRIX), both precisions, under ASan+UBSan.
MASS_SPD_CFG := -DEDMI_MAX_BODIES=4 -DEDMI_MAX_MASS_GAP=3
MASS_SPD_SRC := tests/programs/mass_spd.c tests/lib/harness.c
MASS_SPD_BINS := $(BUILD)/mass_spd-double/mass_spd $(BUILD)/mass_spd-float/mass_spd
$(BUILD)/mass_spd-%/mass_spd: $(MASS_SPD_SRC) tests/lib/host_io.c tests/lib/harness.h edmi.c edmi.h
	mkdir -p $(@D)
	$(CC) $(LIBFLAGS) -O1 -g -fsanitize=address,undefined -fno-sanitize-recover=all \
	    -DEDMI_REAL=$* $(MASS_SPD_CFG) $(TEST_INC) $(MASS_SPD_SRC) tests/lib/host_io.c edmi.c -o $@ $(LDLIBS)

# The worked user potential (examples/morse.c): its callbacks checked as the built-ins are, and
# its runs' energy and momenta, in both precisions (morse --check).
MORSE_BINS := $(BUILD)/morse-double/morse $(BUILD)/morse-float/morse
$(BUILD)/morse-%/morse: examples/morse.c edmi.c edmi.h
	mkdir -p $(@D)
	$(CC) $(STRICT) -O2 -DEDMI_REAL=$* -I. examples/morse.c edmi.c -o $@ $(LDLIBS)

# Leak detection is off: nothing allocates, and LeakSanitizer fails under some containers.
test: $(TEST_BINS) $(CXX_BINS) $(CHECK_OBJS) $(SIM_TEST) $(SIM_REF_BINS) $(REPLAY_BINS) $(BAND_BINS) \
      $(MASS_BINS) $(MASS_SPD_BINS) $(FEAT_BINS) $(MORSE_BINS)
	ASAN_OPTIONS=$${ASAN_OPTIONS:-detect_leaks=0} UBSAN_OPTIONS=$${UBSAN_OPTIONS:-print_stacktrace=1} \
	bash tests/scripts/run_all.sh $(TEST_BINS) $(FEAT_BINS) $(CXX_BINS) '$(SIM_TEST) $(SIM_SCENES)' $(SIM_REF_TESTS) \
	    $(BAND_RUNS) $(MASS_BINS) $(MASS_SPD_BINS) $(foreach b,$(MORSE_BINS),'$(b) --check') \
	    $(foreach b,$(REPLAY_BINS),'$(b) tests/fuzz/corpus') \
	    $(foreach o,$(CHECK_OBJS),'bash tests/scripts/check_lib.sh "$(NM)" "$(CC)" $(o)') \
	    'bash tests/scripts/check_flags.sh "$(CC)"' $(if $(shell command -v clang),'bash tests/scripts/check_flags.sh clang') \
	    'bash tests/scripts/check_help.sh' 'bash tests/scripts/check_docs.sh'

# ---- soak: the guard's adversarial scenes for 10^6 steps per case, in both precisions ---------
# tests/programs/soak.c; the inequality H_n+1 - H_n <= W is checked after every step in tp_q
# (tests/lib/passive.c: __float128 on the x86-64 host, no libquadmath).
SOAK_STEPS ?= 1000000
SOAK_SRC := tests/programs/soak.c tests/lib/passive.c tests/lib/harness.c tests/lib/host_io.c
$(BUILD)/soak-%/soak: $(SOAK_SRC) tests/lib/passive.h tests/lib/harness.h edmi.c edmi.h
	mkdir -p $(@D)
	$(CC) $(STRICT) -O2 -DEDMI_REAL=$* $(TEST_INC) $(SOAK_SRC) edmi.c -o $@ $(LDLIBS)

soak: $(BUILD)/soak-float/soak $(BUILD)/soak-double/soak
	bash tests/scripts/run_all.sh -p '$(BUILD)/soak-float/soak $(SOAK_STEPS)' \
	    '$(BUILD)/soak-double/soak $(SOAK_STEPS)'

# ---- fuzz: every public function under libFuzzer, both precisions (tests/fuzz/) -------------
#   make fuzz FUZZ_TIME=1800   each precision's fuzzer for FUZZ_TIME seconds, side by side
#   make fuzz-cov              edmi.c's line and branch coverage by the corpora
# make test replays the seed corpus tests/fuzz/corpus (reproducers included) with $(CC).
CLANG ?= clang
LLVM_PROFDATA ?= llvm-profdata
LLVM_COV ?= llvm-cov
FUZZ_TIME ?= 60
# Small capacities, so that inputs reach every EDMI_ERR_CAPACITY boundary. The Newton matrix
# store of 300 reals holds the dense matrix up to 5 bodies and, at 6, only a band of pair gap
# 1 (18 rows of 16): the band layout and its refusals are fuzzed too.
FUZZ_CAP := -DEDMI_MAX_BODIES=6 -DEDMI_MAX_LINKS=12 -DEDMI_MAX_DAMPERS=4 -DEDMI_MAX_MATRIX=300 \
            -DEDMI_MAX_MASS_GAP=2 -DEDMI_MAX_WALLS=3
FUZZ_FLAGS := -std=c99 -g -ffp-contract=off -fno-math-errno $(FUZZ_CAP) -I. -Itests/lib
FUZZ_SRC := edmi.c tests/lib/passive.c tests/fuzz/fuzz_api.c
FUZZ_DEPS := $(FUZZ_SRC) edmi.h tests/lib/passive.h
$(BUILD)/fuzz-%/fuzz: $(FUZZ_DEPS)
	mkdir -p $(@D)
	$(CLANG) $(FUZZ_FLAGS) -O1 -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=all \
	    -DEDMI_REAL=$* $(FUZZ_SRC) -o $@ -lm

# The coupling build (FEAT_coupling) too, for a quarter of FUZZ_TIME after the full build:
# its validators refuse what is out with EDMI_ERR_DISABLED, and every promise still holds.
$(BUILD)/fuzz-coupling-%/fuzz: $(FUZZ_DEPS)
	mkdir -p $(@D)
	$(CLANG) $(FUZZ_FLAGS) $(FEAT_coupling) -O1 -fsanitize=fuzzer,address,undefined \
	    -fno-sanitize-recover=all -DEDMI_REAL=$* $(FUZZ_SRC) -o $@ -lm

fuzz: $(foreach r,double float,$(BUILD)/fuzz-$(r)/fuzz $(BUILD)/fuzz-coupling-$(r)/fuzz)
	EDMI_TEST_TIMEOUT=$$(($(FUZZ_TIME) + 300)) \
	bash tests/scripts/run_all.sh 'bash tests/fuzz/run.sh $(FUZZ_TIME) $(BUILD) double float' \
	    'bash tests/fuzz/run.sh $$(($(FUZZ_TIME) / 4)) $(BUILD) coupling-double coupling-float'

$(BUILD)/replay-%/replay: $(FUZZ_DEPS) tests/fuzz/replay.c
	mkdir -p $(@D)
	$(CC) $(FUZZ_FLAGS) $(SAN) -DEDMI_REAL=$* $(FUZZ_SRC) tests/fuzz/replay.c -o $@ $(LDLIBS)

$(BUILD)/fuzzcov-%/replay: $(FUZZ_DEPS) tests/fuzz/replay.c
	mkdir -p $(@D)
	$(CLANG) $(FUZZ_FLAGS) -O1 -fprofile-instr-generate -fcoverage-mapping -DEDMI_REAL=$* \
	    $(FUZZ_SRC) tests/fuzz/replay.c -o $@ -lm

fuzz-cov: $(BUILD)/fuzzcov-double/replay $(BUILD)/fuzzcov-float/replay
	bash tests/fuzz/cov.sh $(BUILD) $(LLVM_PROFDATA) $(LLVM_COV)

# ---- refs: the double-precision reference of tests/test_track.c (tests/ref_track.h) ----------
# Regenerate after a change to the library that moves double results; the double test suite
# fails while the checked-in table is stale.
$(BUILD)/gen_ref: tests/gen_ref.c edmi.c edmi.h
	mkdir -p $(@D)
	$(CC) $(STRICT) -O2 -DEDMI_REAL=double -I. tests/gen_ref.c edmi.c -o $@ $(LDLIBS)

refs: $(BUILD)/gen_ref
	$(BUILD)/gen_ref > tests/ref_track.h

# ---- cross: Cortex-M4F, single precision, no double maths ------------------------------------
$(BUILD)/cross/edmi.o: edmi.c edmi.h | $(BUILD)/cross
	$(ARM_CC) $(LIBFLAGS) $(ARM_TARGET) -Os -ffreestanding -DEDMI_REAL=float -c $< -o $@

# The checks of every cross object, this one's included (m4f-float), run in port/target.mk's
# tgt-cross, whose closing line is their total: .ci/run adds up one line per make target.
cross: $(BUILD)/cross/edmi.o
	$(ARM_SIZE) $<

# ---- cmake-check: edmi through CMake, host and Cortex-M4F (tests/scripts/cmake_check.sh) --------------
.PHONY: cmake-check
cmake-check:
	bash tests/scripts/cmake_check.sh $(BUILD)

# ---- housekeeping ----------------------------------------------------------------------------
$(HOST) $(CHECK) $(BUILD)/cross $(foreach c,$(CONFIGS),$(BUILD)/test-$(c)):
	mkdir -p $@

clean:
	rm -rf $(BUILD)

help:
	@sed -n 's/^#> \{0,1\}//p' Makefile
include port/target.mk
