# port/target.mk: cross builds, emulated-target tests and measurements.
# Included at the end of the top-level Makefile with `include port/target.mk`; uses its
# CC, STRICT, LIBFLAGS, BUILD, ARM_CC, ARM_NM, ARM_SIZE, MASS_CFG, MASS_SPD_CFG and defines only
# TGT_* names.
#
#   make cross          (adds to it) edmi.c for Cortex-M4F (float), Cortex-M7 (double),
#                       Cortex-M0+ (soft float) and RISC-V rv32imac (-nostdlib): external-
#                       reference checks, a link of port/fw_min.c that must leave nothing
#                       undefined, the size table per target and the size per capacity setting
#   make test-target    the unit test suite on QEMU mps2-an386 (Cortex-M4F, EDMI_REAL=float;
#                       also in the coupling build) and mps2-an500 (Cortex-M7, double),
#                       tests/programs/mass_matrix.c built
#                       with the general mass matrix (MASS_CFG) and tests/programs/mass_spd.c with
#                       every pair of 4 bodies coupled (MASS_SPD_CFG); last line "N passed,
#                       N failed"
#   make bench-target   instructions per step (mean and worst), Newton iterations per step,
#                       stack high-water mark of edmi_step, the pieces and bound of a step's
#                       worst case and forced fallback steps, on QEMU with -icount shift=0
#                       (tests/bench/bench_target.c); for the M4F also at a one-body capacity
#   make worst-target   the costliest step of a one-body virtual coupling (the coupling build
#                       at 1 body, 2 links) that a search can make on the Cortex-M4F, and the
#                       bound the count of its pieces gives (tests/bench/worst_target.c; WT_FLAGS=
#                       '-DWT_RANDOM=n -DWT_CLIMB=n' sets the search's size)
#   make haptic-target  the 1 kHz virtual coupling of examples/haptic.c on the Cortex-M4F
#                       (float): instructions per tick, mean and worst, guard actions,
#                       failures, passivity of every tick (tests/bench/haptic_target.c)
#   make check-ram      the RAM formula of docs/sizing.md against sizeof
#   make check-port     check-ram, plus port/riscv/sqrt.c against the host's libm
#   make smoke-target   the target runner itself: a pass, a failed check, a fault, a hang and
#                       a stack overflow must give exit statuses 0, 1, 3, 124 and 4
# Override: TGT_TIMEOUT (seconds per QEMU run, default 600), TGT_QEMU, TGT_RV_CC.

TGT_SAVED_GOAL := $(.DEFAULT_GOAL)

BUILD ?= build
ARM_CC ?= arm-none-eabi-gcc
ARM_NM ?= arm-none-eabi-nm
ARM_SIZE ?= arm-none-eabi-size
TGT_RV_CC ?= riscv64-unknown-elf-gcc
TGT_RV_NM ?= riscv64-unknown-elf-nm
TGT_RV_SIZE ?= riscv64-unknown-elf-size
TGT_QEMU ?= qemu-system-arm
TGT_TIMEOUT ?= 600

TGT := $(BUILD)/target
# The library as a firmware would build it; tests and benchmarks around it at -O2.
TGT_LIB_OPT := -Os -ffreestanding
TGT_APP_OPT := -O2 -g

TGT_FLAGS_m4f := -mcpu=cortex-m4 -mthumb -mfpu=fpv4-sp-d16 -mfloat-abi=hard
TGT_FLAGS_m7 := -mcpu=cortex-m7 -mthumb -mfpu=fpv5-d16 -mfloat-abi=hard
TGT_FLAGS_m0plus := -mcpu=cortex-m0plus -mthumb -mfloat-abi=soft
TGT_FLAGS_rv32imac := -march=rv32imac -mabi=ilp32
TGT_CC_m4f = $(ARM_CC)
TGT_CC_m7 = $(ARM_CC)
TGT_CC_m0plus = $(ARM_CC)
TGT_CC_rv32imac = $(TGT_RV_CC)
TGT_NM_m4f = $(ARM_NM)
TGT_NM_m7 = $(ARM_NM)
TGT_NM_m0plus = $(ARM_NM)
TGT_NM_rv32imac = $(TGT_RV_NM)
TGT_SIZE_m4f = $(ARM_SIZE)
TGT_SIZE_m7 = $(ARM_SIZE)
TGT_SIZE_m0plus = $(ARM_SIZE)
TGT_SIZE_rv32imac = $(TGT_RV_SIZE)
# What the minimal firmware links against: newlib and libgcc on the Arm cores (whatever of
# them edmi.o needs: memcpy, sqrtf/sqrt and soft float on the M0+, possibly nothing); on
# rv32imac with -nostdlib only libgcc and port/riscv (sqrtf/sqrt, mem*).
TGT_FWLINK_m4f := -nostartfiles --specs=nano.specs
TGT_FWLINK_m7 := -nostartfiles --specs=nano.specs
TGT_FWLINK_m0plus := -nostartfiles --specs=nano.specs
TGT_FWLINK_rv32imac := -nostdlib -Wl,--no-warn-rwx-segments
TGT_FWLIBS_m4f := -lm -lc -lgcc
TGT_FWLIBS_m7 := -lm -lc -lgcc
TGT_FWLIBS_m0plus := -lm -lc -lgcc
TGT_FWLIBS_rv32imac := -lgcc
TGT_FWPORT_rv32imac = $(TGT)/port-rv32imac/sqrt.o $(TGT)/port-rv32imac/mem.o
TGT_LABEL_m4f := Cortex-M4F, fpv4-sp-d16 hard-float
TGT_LABEL_m7 := Cortex-M7, fpv5-d16 hard-float
TGT_LABEL_m0plus := Cortex-M0+, soft float
TGT_LABEL_rv32imac := RISC-V rv32imac ilp32, -nostdlib

# Target-precision pairs of `make cross`: the four the issue names, then the soft-float cores
# in the other precision for comparison.
TGT_CROSS := m4f-float m7-double m0plus-float rv32imac-float m0plus-double rv32imac-double
tgt_arch = $(firstword $(subst -, ,$(1)))
tgt_real = $(lastword $(subst -, ,$(1)))
# Float builds on every core must not contain double arithmetic.
tgt_nodouble = $(if $(filter float,$(call tgt_real,$(1))),--no-double)

# Capacity settings N-L-D (EDMI_MAX_BODIES, EDMI_MAX_LINKS, EDMI_MAX_DAMPERS); the last is
# the default. Sizes shown for the M4F (float) and M7 (double). D = 0 compiles dampers out:
# 1-1-0 against 1-1-1 and 16-64-0 against 16-64-16 is the flash and RAM that saves.
TGT_CAPS := 1-1-0 1-1-1 2-1-1 4-8-2 16-64-0 16-64-16 16-64-16-m1
TGT_CAP_TARGETS := m4f-float m7-double
tgt_capdefs = -DEDMI_MAX_BODIES=$(word 1,$(subst -, ,$(1))) \
              -DEDMI_MAX_LINKS=$(word 2,$(subst -, ,$(1))) \
              -DEDMI_MAX_DAMPERS=$(word 3,$(subst -, ,$(1))) \
              $(foreach x,$(wordlist 4,5,$(subst -, ,$(1))),\
                  $(if $(filter m%,$(x)),-DEDMI_MAX_MASS_GAP=$(patsubst m%,%,$(x)),\
                  $(if $(filter w%,$(x)),-DEDMI_MAX_WALLS=$(patsubst w%,%,$(x)),\
                  -DEDMI_MAX_MATRIX=$(x))))

.PHONY: tgt-cross test-target bench-target worst-target haptic-target check-ram check-sqrt check-port study-target \
        smoke-target
cross: tgt-cross

# ---- cross: one directory per target-precision pair -----------------------------------------
# $(1) = pair, e.g. m4f-float
define tgt_cross_rules
$(TGT)/cross-$(1)/edmi.o: edmi.c edmi.h
	@mkdir -p $$(@D)
	$$(TGT_CC_$(call tgt_arch,$(1))) $$(LIBFLAGS) $$(TGT_FLAGS_$(call tgt_arch,$(1))) \
	    $$(TGT_LIB_OPT) -DEDMI_REAL=$(call tgt_real,$(1)) -c $$< -o $$@
$(TGT)/cross-$(1)/fw_min.o: port/fw_min.c edmi.h
	@mkdir -p $$(@D)
	$$(TGT_CC_$(call tgt_arch,$(1))) $$(LIBFLAGS) $$(TGT_FLAGS_$(call tgt_arch,$(1))) \
	    $$(TGT_LIB_OPT) -DEDMI_REAL=$(call tgt_real,$(1)) -I. -c $$< -o $$@
$(TGT)/cross-$(1)/fw_min.elf: $(TGT)/cross-$(1)/fw_min.o $(TGT)/cross-$(1)/edmi.o \
		$$(TGT_FWPORT_$(call tgt_arch,$(1)))
	$$(TGT_CC_$(call tgt_arch,$(1))) $$(TGT_FLAGS_$(call tgt_arch,$(1))) \
	    $$(TGT_FWLINK_$(call tgt_arch,$(1))) -Wl,-e,main -Wl,--gc-sections $$^ \
	    $$(TGT_FWLIBS_$(call tgt_arch,$(1))) -o $$@
endef
$(foreach p,$(TGT_CROSS),$(eval $(call tgt_cross_rules,$(p))))

# port/riscv: the square root and mem* for -nostdlib. -fno-builtin and
# -fno-tree-loop-distribute-patterns stop GCC from turning the mem* loops into calls to
# themselves.
$(TGT)/port-rv32imac/%.o: port/riscv/%.c
	@mkdir -p $(@D)
	$(TGT_RV_CC) $(LIBFLAGS) $(TGT_FLAGS_rv32imac) -Os -ffreestanding -fno-builtin \
	    -fno-tree-loop-distribute-patterns -c $< -o $@

# $(1) = pair, $(2) = capacity N-L-D: edmi.o text and sizeof for the capacity table.
define tgt_cap_rules
$(TGT)/cap-$(1)/$(2)/edmi.o: edmi.c edmi.h
	@mkdir -p $$(@D)
	$$(TGT_CC_$(call tgt_arch,$(1))) $$(LIBFLAGS) $$(TGT_FLAGS_$(call tgt_arch,$(1))) \
	    $$(TGT_LIB_OPT) -DEDMI_REAL=$(call tgt_real,$(1)) $(call tgt_capdefs,$(2)) -c $$< -o $$@
$(TGT)/cap-$(1)/$(2)/ramsize.o: port/ramcheck.c edmi.h
	@mkdir -p $$(@D)
	$$(TGT_CC_$(call tgt_arch,$(1))) $$(STRICT) $$(TGT_FLAGS_$(call tgt_arch,$(1))) \
	    -DTGT_RAMCHECK_SIZES_ONLY -DEDMI_REAL=$(call tgt_real,$(1)) $(call tgt_capdefs,$(2)) -I. \
	    -c $$< -o $$@
endef
$(foreach p,$(TGT_CAP_TARGETS),$(foreach c,$(TGT_CAPS),$(eval $(call tgt_cap_rules,$(p),$(c)))))

# Build options (edmi.h, EDMI_WITH_*) on the Cortex-M4F, float, -Os: each feature alone
# compiled out of the default build (an upper-case name X is -DEDMI_WITH_X=0; DAMPERS is
# EDMI_MAX_DAMPERS=0), walls compiled in (WALLS-6: EDMI_MAX_WALLS=6), then the configurations the Makefile tests (FEAT_*), and coupling at a
# one-body capacity (1 body, 2 links), without and with the damper README's haptic recipe adds.
TGT_OPTS := default MP LG LG_QUOTIENT GE PM PT HARMONIC QUARTIC NEO_HOOKE LJ INVERSE USER CONTACT \
            FIELD PORTS SCENE DAMPERS WALLS-6 $(FEATURES) coupling-1 coupling-damper-1
FEAT_coupling-1 = $(FEAT_coupling) -DEDMI_MAX_BODIES=1 -DEDMI_MAX_LINKS=2
FEAT_coupling-damper-1 = $(filter-out -DEDMI_MAX_DAMPERS=0,$(FEAT_coupling-1)) -DEDMI_MAX_DAMPERS=1
tgt_optdefs = $(if $(filter default,$(1)),,$(if $(filter DAMPERS,$(1)),-DEDMI_MAX_DAMPERS=0,\
                  $(if $(filter WALLS-6,$(1)),-DEDMI_MAX_WALLS=6,\
                  $(if $(FEAT_$(1)),$(FEAT_$(1)),-DEDMI_WITH_$(1)=0))))
$(TGT)/opt-m4f-float/%/edmi.o: edmi.c edmi.h
	@mkdir -p $(@D)
	$(ARM_CC) $(LIBFLAGS) $(TGT_FLAGS_m4f) $(TGT_LIB_OPT) -DEDMI_REAL=float \
	    $(call tgt_optdefs,$*) -c $< -o $@
TGT_OPT_OBJS := $(foreach o,$(TGT_OPTS),$(TGT)/opt-m4f-float/$(o)/edmi.o)
TGT_OPT_DESC_default := every feature in
TGT_OPT_DESC_decaying := the energy-safe schemes GE, PM, PT (MP and LG out)
TGT_OPT_DESC_coupling := one PM virtual coupling: PM, harmonic, anchors and moving anchors, \
    the guard (every other scheme and potential, the field, ports, scene loader, dampers out)
TGT_OPT_DESC_conservative := MP and LG without the guard
TGT_OPT_DESC_coupling-1 := coupling at a capacity of 1 body and 2 links
TGT_OPT_DESC_coupling-damper-1 := coupling-1 with one damper, as the haptic recipe of the README
tgt_optdesc = $(strip $(if $(TGT_OPT_DESC_$(1)),$(TGT_OPT_DESC_$(1)),$(call tgt_optdefs,$(1))))

TGT_CROSS_OBJS := $(foreach p,$(TGT_CROSS),$(TGT)/cross-$(p)/edmi.o $(TGT)/cross-$(p)/fw_min.elf)
TGT_CAP_OBJS := $(foreach p,$(TGT_CAP_TARGETS),$(foreach c,$(TGT_CAPS),\
                    $(TGT)/cap-$(p)/$(c)/edmi.o $(TGT)/cap-$(p)/$(c)/ramsize.o))

tgt-cross: $(TGT_CROSS_OBJS) $(TGT_CAP_OBJS) $(TGT_OPT_OBJS)
	@echo "### external references of edmi.o per target (tests/scripts/check_lib.sh)"
	@bash tests/scripts/run_all.sh $(foreach p,$(TGT_CROSS),'bash tests/scripts/check_lib.sh \
	    "$(TGT_NM_$(call tgt_arch,$(p)))" \
	    "$(TGT_CC_$(call tgt_arch,$(p))) $(TGT_FLAGS_$(call tgt_arch,$(p)))" \
	    $(TGT)/cross-$(p)/edmi.o $(call tgt_nodouble,$(p))')
	@echo "### size per target: edmi.c at -Os (Berkeley size), and port/fw_min.c linked"
	@bash port/size_table.sh targets $(foreach p,$(TGT_CROSS),\
	    '$(TGT_LABEL_$(call tgt_arch,$(p))), $(call tgt_real,$(p))' \
	    $(TGT_SIZE_$(call tgt_arch,$(p))) $(TGT_NM_$(call tgt_arch,$(p))) \
	    $(TGT)/cross-$(p)/edmi.o $(TGT)/cross-$(p)/fw_min.elf)
	@echo "### size per capacity setting: flash (edmi.o text) and RAM in bytes"
	@bash port/size_table.sh capacity '$(TGT_CAPS)' $(foreach p,$(TGT_CAP_TARGETS),\
	    '$(firstword $(subst $(TGT_COMMA), ,$(TGT_LABEL_$(call tgt_arch,$(p))))) $(call tgt_real,$(p))' \
	    $(TGT_SIZE_$(call tgt_arch,$(p))) $(TGT_NM_$(call tgt_arch,$(p))) $(TGT)/cap-$(p))
	@echo "### size per build option: Cortex-M4F, float, -Os, edmi.o text in bytes"
	@bash port/size_table.sh options $(ARM_SIZE) $(foreach o,$(TGT_OPTS),\
	    '$(o)' '$(call tgt_optdesc,$(o))' $(TGT)/opt-m4f-float/$(o)/edmi.o)

# ---- the emulated boards: start-up, semihosting, linker script --------------------------------
TGT_BOARDS := an386 an500
TGT_MACHINE_an386 := mps2-an386
TGT_MACHINE_an500 := mps2-an500
TGT_ARCH_an386 := m4f
TGT_ARCH_an500 := m7
TGT_REAL_an386 := float
TGT_REAL_an500 := double
TGT_LD := port/cortex-m/mps2.ld
TGT_PORT_HDR := $(wildcard port/cortex-m/*.h)
TGT_TEST_SRC = $(wildcard tests/test_*.c) tests/lib/harness.c tests/lib/target_io.c tests/lib/scenes.c \
               tests/lib/passive.c
TGT_TEST_HDR = $(wildcard tests/*.h tests/lib/*.h)
# Tests and benchmarks include edmi.h, the shared helpers of tests/lib and the port's
# cortex-m/*.h by bare name.
TGT_INC := -I. -Itests/lib -Iport
# The haptic benchmark measures the example's own hand model (examples/haptic_hand.h).
TGT_INC_haptic_target := -Iexamples
# An object per source in $(1), named tests-<base name>.o, whichever folder holds the source.
tgt_test_obj = $(addprefix $(1)/tests-,$(notdir $(patsubst %.c,%.o,$(2))))
TGT_MASS_SRC = tests/programs/mass_matrix.c tests/lib/harness.c tests/lib/passive.c tests/lib/target_io.c
TGT_MASS_SPD_SRC = tests/programs/mass_spd.c tests/lib/harness.c tests/lib/target_io.c

# $(1) = board. Objects of the board's programs in $(TGT)/$(1)/.
define tgt_board_rules
$(TGT)/$(1)/edmi.o: edmi.c edmi.h
	@mkdir -p $$(@D)
	$$(ARM_CC) $$(LIBFLAGS) $$(TGT_FLAGS_$$(TGT_ARCH_$(1))) $$(TGT_LIB_OPT) \
	    -DEDMI_REAL=$$(TGT_REAL_$(1)) -c $$< -o $$@
$(TGT)/$(1)/startup.o: port/cortex-m/startup.S
	@mkdir -p $$(@D)
	$$(ARM_CC) $$(TGT_FLAGS_$$(TGT_ARCH_$(1))) -c $$< -o $$@
$(TGT)/$(1)/port-%.o: port/cortex-m/%.c $$(TGT_PORT_HDR)
	@mkdir -p $$(@D)
	$$(ARM_CC) $$(LIBFLAGS) $$(TGT_FLAGS_$$(TGT_ARCH_$(1))) $$(TGT_APP_OPT) -c $$< -o $$@
# the suite with walls compiled in (TEST_CAP), as on the host; the programs below link the
# library at its defaults, with helpers built the same way (lib-%.o)
$(TGT)/$(1)/edmi-tests.o: edmi.c edmi.h
	@mkdir -p $$(@D)
	$$(ARM_CC) $$(LIBFLAGS) $$(TGT_FLAGS_$$(TGT_ARCH_$(1))) $$(TGT_LIB_OPT) $$(TEST_CAP) \
	    -DEDMI_REAL=$$(TGT_REAL_$(1)) -c $$< -o $$@
$(TGT)/$(1)/tests-%.o: tests/%.c edmi.h $$(TGT_TEST_HDR) $$(TGT_PORT_HDR)
	@mkdir -p $$(@D)
	$$(ARM_CC) $$(STRICT) $$(TGT_FLAGS_$$(TGT_ARCH_$(1))) $$(TGT_APP_OPT) $$(TEST_CAP) $$(TGT_INC) \
	    -DEDMI_REAL=$$(TGT_REAL_$(1)) -c $$< -o $$@
$(TGT)/$(1)/tests-%.o: tests/lib/%.c edmi.h $$(TGT_TEST_HDR) $$(TGT_PORT_HDR)
	@mkdir -p $$(@D)
	$$(ARM_CC) $$(STRICT) $$(TGT_FLAGS_$$(TGT_ARCH_$(1))) $$(TGT_APP_OPT) $$(TEST_CAP) $$(TGT_INC) \
	    -DEDMI_REAL=$$(TGT_REAL_$(1)) -c $$< -o $$@
$(TGT)/$(1)/app-%.o: tests/bench/%.c edmi.h $$(TGT_TEST_HDR) $$(TGT_PORT_HDR)
	@mkdir -p $$(@D)
	$$(ARM_CC) $$(STRICT) -Werror $$(TGT_FLAGS_$$(TGT_ARCH_$(1))) $$(TGT_APP_OPT) $$(TGT_INC) \
	    $$(TGT_INC_$$*) -DEDMI_REAL=$$(TGT_REAL_$(1)) -c $$< -o $$@
$(TGT)/$(1)/app-smoke_%.o: port/smoke_test.c edmi.h $$(TGT_TEST_HDR) $$(TGT_PORT_HDR)
	@mkdir -p $$(@D)
	$$(ARM_CC) $$(STRICT) $$(TGT_FLAGS_$$(TGT_ARCH_$(1))) $$(TGT_APP_OPT) $$(TGT_INC) \
	    -DEDMI_REAL=$$(TGT_REAL_$(1)) -DTGT_SMOKE_$$* -c $$< -o $$@
TGT_RT_$(1) := $(TGT)/$(1)/startup.o $(TGT)/$(1)/port-crt.o $(TGT)/$(1)/port-semihost.o
$(TGT)/$(1)/edmi_tests.elf: $(TGT)/$(1)/edmi-tests.o $$(TGT_RT_$(1)) \
		$$(call tgt_test_obj,$(TGT)/$(1),$$(TGT_TEST_SRC)) $(TGT_LD)
	$$(ARM_CC) $$(TGT_FLAGS_$$(TGT_ARCH_$(1))) -nostartfiles -T $(TGT_LD) --specs=nano.specs \
	    -Wl,--gc-sections -Wl,-Map=$$@.map $$(filter %.o,$$^) -lm -lc -lgcc -o $$@
$(TGT)/$(1)/bench_target.elf: $(TGT)/$(1)/edmi.o $$(TGT_RT_$(1)) $(TGT)/$(1)/app-bench_target.o \
		$(TGT_LD)
	$$(ARM_CC) $$(TGT_FLAGS_$$(TGT_ARCH_$(1))) -nostartfiles -T $(TGT_LD) --specs=nano.specs \
	    -Wl,--gc-sections $$(filter %.o,$$^) -lm -lc -lgcc -o $$@
$(TGT)/$(1)/app-haptic_target.o: examples/haptic_hand.h
$(TGT)/$(1)/haptic_target.elf: $(TGT)/$(1)/edmi.o $$(TGT_RT_$(1)) $(TGT)/$(1)/app-haptic_target.o \
		$(TGT_LD)
	$$(ARM_CC) $$(TGT_FLAGS_$$(TGT_ARCH_$(1))) -nostartfiles -T $(TGT_LD) --specs=nano.specs \
	    -Wl,--gc-sections $$(filter %.o,$$^) -lm -lc -lgcc -o $$@
# tests/programs/mass_matrix.c with the general mass matrix on: every object built with MASS_CFG
$(TGT)/$(1)-mass/edmi.o: edmi.c edmi.h
	@mkdir -p $$(@D)
	$$(ARM_CC) $$(LIBFLAGS) $$(TGT_FLAGS_$$(TGT_ARCH_$(1))) $$(TGT_LIB_OPT) \
	    -DEDMI_REAL=$$(TGT_REAL_$(1)) $$(MASS_CFG) -c $$< -o $$@
$(TGT)/$(1)-mass/tests-%.o: tests/lib/%.c edmi.h $$(TGT_TEST_HDR) $$(TGT_PORT_HDR)
	@mkdir -p $$(@D)
	$$(ARM_CC) $$(STRICT) $$(TGT_FLAGS_$$(TGT_ARCH_$(1))) $$(TGT_APP_OPT) $$(TGT_INC) \
	    -DEDMI_REAL=$$(TGT_REAL_$(1)) $$(MASS_CFG) -c $$< -o $$@
$(TGT)/$(1)-mass/tests-%.o: tests/programs/%.c edmi.h $$(TGT_TEST_HDR) $$(TGT_PORT_HDR)
	@mkdir -p $$(@D)
	$$(ARM_CC) $$(STRICT) $$(TGT_FLAGS_$$(TGT_ARCH_$(1))) $$(TGT_APP_OPT) $$(TGT_INC) \
	    -DEDMI_REAL=$$(TGT_REAL_$(1)) $$(MASS_CFG) -c $$< -o $$@
$(TGT)/$(1)-mass/mass_tests.elf: $(TGT)/$(1)-mass/edmi.o $$(TGT_RT_$(1)) \
		$$(call tgt_test_obj,$(TGT)/$(1)-mass,$$(TGT_MASS_SRC)) $(TGT_LD)
	$$(ARM_CC) $$(TGT_FLAGS_$$(TGT_ARCH_$(1))) -nostartfiles -T $(TGT_LD) --specs=nano.specs \
	    -Wl,--gc-sections $$(filter %.o,$$^) -lm -lc -lgcc -o $$@
# tests/programs/mass_spd.c: every object built with MASS_SPD_CFG
$(TGT)/$(1)-spd/edmi.o: edmi.c edmi.h
	@mkdir -p $$(@D)
	$$(ARM_CC) $$(LIBFLAGS) $$(TGT_FLAGS_$$(TGT_ARCH_$(1))) $$(TGT_LIB_OPT) \
	    -DEDMI_REAL=$$(TGT_REAL_$(1)) $$(MASS_SPD_CFG) -c $$< -o $$@
$(TGT)/$(1)-spd/tests-%.o: tests/lib/%.c edmi.h $$(TGT_TEST_HDR) $$(TGT_PORT_HDR)
	@mkdir -p $$(@D)
	$$(ARM_CC) $$(STRICT) $$(TGT_FLAGS_$$(TGT_ARCH_$(1))) $$(TGT_APP_OPT) $$(TGT_INC) \
	    -DEDMI_REAL=$$(TGT_REAL_$(1)) $$(MASS_SPD_CFG) -c $$< -o $$@
$(TGT)/$(1)-spd/tests-%.o: tests/programs/%.c edmi.h $$(TGT_TEST_HDR) $$(TGT_PORT_HDR)
	@mkdir -p $$(@D)
	$$(ARM_CC) $$(STRICT) $$(TGT_FLAGS_$$(TGT_ARCH_$(1))) $$(TGT_APP_OPT) $$(TGT_INC) \
	    -DEDMI_REAL=$$(TGT_REAL_$(1)) $$(MASS_SPD_CFG) -c $$< -o $$@
$(TGT)/$(1)-spd/mass_spd.elf: $(TGT)/$(1)-spd/edmi.o $$(TGT_RT_$(1)) \
		$$(call tgt_test_obj,$(TGT)/$(1)-spd,$$(TGT_MASS_SPD_SRC)) $(TGT_LD)
	$$(ARM_CC) $$(TGT_FLAGS_$$(TGT_ARCH_$(1))) -nostartfiles -T $(TGT_LD) --specs=nano.specs \
	    -Wl,--gc-sections $$(filter %.o,$$^) -lm -lc -lgcc -o $$@
$(TGT)/$(1)/lib-%.o: tests/lib/%.c edmi.h $$(TGT_TEST_HDR) $$(TGT_PORT_HDR)
	@mkdir -p $$(@D)
	$$(ARM_CC) $$(STRICT) $$(TGT_FLAGS_$$(TGT_ARCH_$(1))) $$(TGT_APP_OPT) $$(TGT_INC) \
	    -DEDMI_REAL=$$(TGT_REAL_$(1)) -c $$< -o $$@
$(TGT)/$(1)/smoke-%.elf: $(TGT)/$(1)/edmi.o $$(TGT_RT_$(1)) $(TGT)/$(1)/app-smoke_%.o \
		$(TGT)/$(1)/lib-harness.o $(TGT)/$(1)/lib-target_io.o $(TGT_LD)
	$$(ARM_CC) $$(TGT_FLAGS_$$(TGT_ARCH_$(1))) -nostartfiles -T $(TGT_LD) --specs=nano.specs \
	    -Wl,--gc-sections $$(filter %.o,$$^) -lm -lc -lgcc -o $$@
endef
$(foreach b,$(TGT_BOARDS),$(eval $(call tgt_board_rules,$(b))))

TGT_RUN = TGT_TIMEOUT=$(TGT_TIMEOUT) TGT_QEMU=$(TGT_QEMU) bash port/run_qemu.sh

# The suite once more on the Cortex-M4F in the coupling build (FEAT_coupling: what a haptic
# firmware carries), skipping the cases that need what it leaves out.
TGT_FEAT := $(TGT)/an386-coupling
$(TGT_FEAT)/edmi.o: edmi.c edmi.h
	@mkdir -p $(@D)
	$(ARM_CC) $(LIBFLAGS) $(TGT_FLAGS_m4f) $(TGT_LIB_OPT) -DEDMI_REAL=float $(FEAT_coupling) \
	    -c $< -o $@
$(TGT_FEAT)/tests-%.o: tests/%.c edmi.h $(TGT_TEST_HDR) $(TGT_PORT_HDR)
	@mkdir -p $(@D)
	$(ARM_CC) $(STRICT) $(TGT_FLAGS_m4f) $(TGT_APP_OPT) $(TGT_INC) -DEDMI_REAL=float $(FEAT_coupling) \
	    -c $< -o $@
$(TGT_FEAT)/tests-%.o: tests/lib/%.c edmi.h $(TGT_TEST_HDR) $(TGT_PORT_HDR)
	@mkdir -p $(@D)
	$(ARM_CC) $(STRICT) $(TGT_FLAGS_m4f) $(TGT_APP_OPT) $(TGT_INC) -DEDMI_REAL=float $(FEAT_coupling) \
	    -c $< -o $@
$(TGT_FEAT)/edmi_tests.elf: $(TGT_FEAT)/edmi.o $(TGT_RT_an386) \
		$(call tgt_test_obj,$(TGT_FEAT),$(TGT_TEST_SRC)) $(TGT_LD)
	$(ARM_CC) $(TGT_FLAGS_m4f) -nostartfiles -T $(TGT_LD) --specs=nano.specs \
	    -Wl,--gc-sections $(filter %.o,$^) -lm -lc -lgcc -o $@

test-target: $(foreach b,$(TGT_BOARDS),$(TGT)/$(b)/edmi_tests.elf $(TGT)/$(b)-mass/mass_tests.elf \
		$(TGT)/$(b)-spd/mass_spd.elf) $(TGT_FEAT)/edmi_tests.elf
	EDMI_TEST_TIMEOUT=$$(($(TGT_TIMEOUT) + 30)) bash tests/scripts/run_all.sh \
	    $(foreach b,$(TGT_BOARDS),'$(TGT_RUN) $(TGT_MACHINE_$(b)) $(TGT)/$(b)/edmi_tests.elf' \
	        '$(TGT_RUN) $(TGT_MACHINE_$(b)) $(TGT)/$(b)-mass/mass_tests.elf' \
	        '$(TGT_RUN) $(TGT_MACHINE_$(b)) $(TGT)/$(b)-spd/mass_spd.elf') \
	    '$(TGT_RUN) $(TGT_MACHINE_an386) $(TGT_FEAT)/edmi_tests.elf'

# The benchmark once more on the Cortex-M4F for a one-body capacity (EDMI_MAX_BODIES, _LINKS,
# _DAMPERS = 1): its bound is that of the smallest build. Same start-up objects.
TGT_BENCH_CAP := 1-1-1
TGT_BENCH_CAP_DIR := $(TGT)/an386-cap$(TGT_BENCH_CAP)
$(TGT_BENCH_CAP_DIR)/edmi.o: edmi.c edmi.h
	@mkdir -p $(@D)
	$(ARM_CC) $(LIBFLAGS) $(TGT_FLAGS_m4f) $(TGT_LIB_OPT) -DEDMI_REAL=float \
	    $(call tgt_capdefs,$(TGT_BENCH_CAP)) -c $< -o $@
$(TGT_BENCH_CAP_DIR)/app-bench_target.o: tests/bench/bench_target.c edmi.h tests/lib/bench_scenes.h \
		$(TGT_PORT_HDR)
	@mkdir -p $(@D)
	$(ARM_CC) $(STRICT) -Werror $(TGT_FLAGS_m4f) $(TGT_APP_OPT) $(TGT_INC) -DEDMI_REAL=float \
	    $(call tgt_capdefs,$(TGT_BENCH_CAP)) -c $< -o $@
$(TGT_BENCH_CAP_DIR)/bench_target.elf: $(TGT_BENCH_CAP_DIR)/edmi.o $(TGT_RT_an386) \
		$(TGT_BENCH_CAP_DIR)/app-bench_target.o $(TGT_LD)
	$(ARM_CC) $(TGT_FLAGS_m4f) -nostartfiles -T $(TGT_LD) --specs=nano.specs \
	    -Wl,--gc-sections $(filter %.o,$^) -lm -lc -lgcc -o $@

# -icount shift=0: one instruction = 1 ns of virtual time, which SysTick counts.
bench-target: $(foreach b,$(TGT_BOARDS),$(TGT)/$(b)/bench_target.elf) \
		$(TGT_BENCH_CAP_DIR)/bench_target.elf
	$(foreach b,$(TGT_BOARDS),$(TGT_RUN) $(TGT_MACHINE_$(b)) $(TGT)/$(b)/bench_target.elf \
	    -icount shift=0 &&) true
	$(TGT_RUN) $(TGT_MACHINE_an386) $(TGT_BENCH_CAP_DIR)/bench_target.elf -icount shift=0

# The costliest step of a one-body virtual coupling on the Cortex-M4F, found by a search
# (tests/bench/worst_target.c): the coupling build (FEAT_coupling) at one body and two links.
TGT_WORST_DIR := $(TGT)/an386-worst
TGT_WORST_CFG := -DEDMI_REAL=float $(FEAT_coupling) -DEDMI_MAX_BODIES=1 -DEDMI_MAX_LINKS=2
$(TGT_WORST_DIR)/edmi.o: edmi.c edmi.h
	@mkdir -p $(@D)
	$(ARM_CC) $(LIBFLAGS) $(TGT_FLAGS_m4f) $(TGT_LIB_OPT) $(TGT_WORST_CFG) -c $< -o $@
$(TGT_WORST_DIR)/app-worst_target.o: tests/bench/worst_target.c edmi.h $(TGT_PORT_HDR)
	@mkdir -p $(@D)
	$(ARM_CC) $(STRICT) -Werror $(TGT_FLAGS_m4f) $(TGT_APP_OPT) $(TGT_INC) $(TGT_WORST_CFG) $(WT_FLAGS) \
	    -c $< -o $@
$(TGT_WORST_DIR)/worst_target.elf: $(TGT_WORST_DIR)/edmi.o $(TGT_RT_an386) \
		$(TGT_WORST_DIR)/app-worst_target.o $(TGT_LD)
	$(ARM_CC) $(TGT_FLAGS_m4f) -nostartfiles -T $(TGT_LD) --specs=nano.specs \
	    -Wl,--gc-sections $(filter %.o,$^) -lm -lc -lgcc -o $@
worst-target: $(TGT_WORST_DIR)/worst_target.elf
	$(TGT_RUN) $(TGT_MACHINE_an386) $< -icount shift=0

# The haptic example on the Cortex-M4F in float, as a firmware would run it; then the same
# coupling pressed into a wall (HT_WALL; the library with one wall, its own object).
TGT_HWALL_DIR := $(TGT)/an386-wall
$(TGT_HWALL_DIR)/edmi.o: edmi.c edmi.h
	@mkdir -p $(@D)
	$(ARM_CC) $(LIBFLAGS) $(TGT_FLAGS_m4f) $(TGT_LIB_OPT) -DEDMI_REAL=float -DEDMI_MAX_WALLS=1 \
	    -c $< -o $@
$(TGT_HWALL_DIR)/app-haptic_target.o: tests/bench/haptic_target.c edmi.h examples/haptic_hand.h \
		$(TGT_PORT_HDR)
	@mkdir -p $(@D)
	$(ARM_CC) $(STRICT) -Werror $(TGT_FLAGS_m4f) $(TGT_APP_OPT) $(TGT_INC) \
	    $(TGT_INC_haptic_target) -DEDMI_REAL=float -DEDMI_MAX_WALLS=1 -DHT_WALL=1 -c $< -o $@
$(TGT_HWALL_DIR)/haptic_target.elf: $(TGT_HWALL_DIR)/edmi.o $(TGT_RT_an386) \
		$(TGT_HWALL_DIR)/app-haptic_target.o $(TGT_LD)
	$(ARM_CC) $(TGT_FLAGS_m4f) -nostartfiles -T $(TGT_LD) --specs=nano.specs \
	    -Wl,--gc-sections $(filter %.o,$^) -lm -lc -lgcc -o $@
haptic-target: $(TGT)/an386/haptic_target.elf $(TGT_HWALL_DIR)/haptic_target.elf
	$(TGT_RUN) $(TGT_MACHINE_an386) $< -icount shift=0
	$(TGT_RUN) $(TGT_MACHINE_an386) $(TGT_HWALL_DIR)/haptic_target.elf -icount shift=0

# The runner must report a clean run as passed and a failed check, a fault, a hang and a stack
# overflow as failed, with the exit statuses 0, 1, 3, 124 and 4.
TGT_SMOKE := OK FAIL FAULT HANG STACK
.SECONDARY: $(foreach s,$(TGT_SMOKE),$(TGT)/an386/app-smoke_$(s).o)
smoke-target: $(foreach s,$(TGT_SMOKE),$(TGT)/an386/smoke-$(s).elf)
	@pass=0; fail=0; for s in $(TGT_SMOKE); do \
	    case $$s in OK) want=0;; FAIL) want=1;; FAULT) want=3;; STACK) want=4;; *) want=124;; esac; \
	    TGT_TIMEOUT=5 TGT_QEMU=$(TGT_QEMU) bash port/run_qemu.sh mps2-an386 \
	        $(TGT)/an386/smoke-$$s.elf > $(TGT)/an386/smoke-$$s.log 2>&1; rc=$$?; \
	    tail -n 3 $(TGT)/an386/smoke-$$s.log | sed "s/^/    smoke-$$s | /"; \
	    if [ "$$rc" = "$$want" ]; then echo "ok   smoke-$$s: exit $$rc"; pass=$$((pass + 1)); \
	    else echo "FAIL smoke-$$s: exit $$rc, want $$want"; fail=$$((fail + 1)); fi; \
	done; echo "$$pass passed, $$fail failed"; test "$$fail" -eq 0

# ---- host checks of port/ ----------------------------------------------------------------------
# RAM formula: every capacity setting in both precisions on the host (LP64), and compiled
# (the formula is a compile-time assertion) for Arm EABI and RISC-V ilp32; 64-63-16-3072 is a
# 64-body chain's band store (EDMI_MAX_MATRIX = 48 N); w3 etc.: EDMI_MAX_WALLS.
TGT_RAM_CAPS := $(TGT_CAPS) 3-5-2 7-2-1 64-63-16-3072 3-5-2-w3 6-7-0-m1-w2 4-8-2-w6
TGT_RAM_HOST := $(foreach r,float double,$(foreach c,$(TGT_RAM_CAPS),$(TGT)/ramcheck/$(r)-$(c)))
TGT_RAM_CROSS := $(foreach a,m4f rv32imac,$(foreach r,float double,$(foreach c,$(TGT_RAM_CAPS),\
                     $(TGT)/ramcheck/$(a)-$(r)-$(c).o)))
define tgt_ram_rules
$(TGT)/ramcheck/$(1)-$(2): port/ramcheck.c edmi.h
	@mkdir -p $$(@D)
	$$(CC) $$(STRICT) -Werror -O2 -DEDMI_REAL=$(1) $(call tgt_capdefs,$(2)) -I. $$< -o $$@
$(TGT)/ramcheck/m4f-$(1)-$(2).o: port/ramcheck.c edmi.h
	@mkdir -p $$(@D)
	$$(ARM_CC) $$(STRICT) -Werror $$(TGT_FLAGS_m4f) -DTGT_RAMCHECK_NO_MAIN -DEDMI_REAL=$(1) -I. \
	    $(call tgt_capdefs,$(2)) -c $$< -o $$@
$(TGT)/ramcheck/rv32imac-$(1)-$(2).o: port/ramcheck.c edmi.h
	@mkdir -p $$(@D)
	$$(TGT_RV_CC) $$(STRICT) -Werror $$(TGT_FLAGS_rv32imac) -DTGT_RAMCHECK_NO_MAIN -I. \
	    -DEDMI_REAL=$(1) $(call tgt_capdefs,$(2)) -c $$< -o $$@
endef
$(foreach r,float double,$(foreach c,$(TGT_RAM_CAPS),$(eval $(call tgt_ram_rules,$(r),$(c)))))

# The cross objects only have to compile; each counts as one passed check.
TGT_RAM_CROSS_OK = echo "compile-time formula checks, Arm EABI and RISC-V ilp32:"; \
    echo "$(words $(TGT_RAM_CROSS)) passed, 0 failed"
check-ram: $(TGT_RAM_HOST) $(TGT_RAM_CROSS)
	bash tests/scripts/run_all.sh $(TGT_RAM_HOST) '$(TGT_RAM_CROSS_OK)'

$(TGT)/sqrtcheck: port/sqrtcheck.c port/riscv/sqrt.c
	@mkdir -p $(@D)
	$(CC) $(STRICT) -Werror -O2 -DTGT_SQRTF_NAME=tgt_sqrtf -DTGT_SQRT_NAME=tgt_sqrt \
	    port/sqrtcheck.c port/riscv/sqrt.c -o $@ -lm

check-sqrt: $(TGT)/sqrtcheck
	bash tests/scripts/run_all.sh $(TGT)/sqrtcheck

check-port: $(TGT_RAM_HOST) $(TGT_RAM_CROSS) $(TGT)/sqrtcheck
	bash tests/scripts/run_all.sh $(TGT_RAM_HOST) $(TGT)/sqrtcheck '$(TGT_RAM_CROSS_OK)'

TGT_COMMA := ,
.DEFAULT_GOAL := $(TGT_SAVED_GOAL)

# The work-precision study's Cortex-M4F column (tests/bench/study_target.c; `make study` runs it).
$(TGT)/an386/study_target.elf: $(TGT)/an386/edmi.o $(TGT_RT_an386) $(TGT)/an386/app-study_target.o \
		$(TGT_LD)
	$(ARM_CC) $(TGT_FLAGS_m4f) -nostartfiles -T $(TGT_LD) --specs=nano.specs \
	    -Wl,--gc-sections $(filter %.o,$^) -lm -lc -lgcc -o $@
study-target: $(TGT)/an386/study_target.elf
	$(TGT_RUN) $(TGT_MACHINE_an386) $< -icount shift=0
