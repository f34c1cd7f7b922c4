/*
 * edmi_config_template.h: every edmi build option in one place.
 * SPDX-License-Identifier: MIT
 *
 * Copy this file into your tree as edmi_config.h, uncomment what you change, and compile
 * EVERY translation unit that includes edmi.h (edmi.c and your own) with
 *     -DEDMI_USER_CONFIG='"edmi_config.h"'
 * (CMake: target_compile_definitions(your_target PUBLIC EDMI_USER_CONFIG="edmi_config.h")).
 * The options change the layout of edmi_system and edmi_workspace, so a translation unit
 * compiled without them sees other sizes: check once at start-up with
 *     if (!EDMI_CONFIG_MATCHES()) { ... a build error, stop ... }
 * Each value below is the default; the costs are those of edmi.h (docs/sizing.md).
 */
#ifndef EDMI_CONFIG_H
#define EDMI_CONFIG_H

/* Precision: float (a Cortex-M4F's single-precision FPU) or double. Changes the ABI. */
/* #define EDMI_REAL float */

/* Bodies per system: 10 reals + 1 int in edmi_system and 32 reals + 6 ints in edmi_workspace
 * per body, plus the Newton matrix below. */
/* #define EDMI_MAX_BODIES 16 */

/* Links (pair or anchor) per system: one edmi_link and 6 reals + 1 int in edmi_system, 56
 * reals + 4 ints in edmi_workspace per link. */
/* #define EDMI_MAX_LINKS 64 */

/* Viscous dampers per system: an int and a real in edmi_system, 9 reals in edmi_workspace.
 * 0 compiles dampers out. */
/* #define EDMI_MAX_DAMPERS 16 */

/* The general mass matrix: the largest body-index gap of a coupled mass (1 for consistent
 * masses of bar elements along a chain); N G reals in edmi_system. 0 compiles it out
 * (docs/mass-matrix.md). */
/* #define EDMI_MAX_MASS_GAP 0 */

/* Reals in the Newton matrix: the dense 9 N^2 by default; a chain of N bodies needs 48 N
 * (docs/api.md, "Solver"). */
/* #define EDMI_MAX_MATRIX (9 * EDMI_MAX_BODIES * EDMI_MAX_BODIES) */

/* Features (flash only: the layouts stay the same). 0 compiles one out; a call that needs it
 * then returns EDMI_ERR_DISABLED (docs/sizing.md, "Build options", has the flash of each).
 * The schemes, at least one: */
/* #define EDMI_WITH_MP 1 */
/* #define EDMI_WITH_LG 1 */
/* #define EDMI_WITH_GE 1 */
/* #define EDMI_WITH_PM 1 */
/* #define EDMI_WITH_PT 1 */
/* LG's quotient form with its alternate forces (default: EDMI_WITH_LG). */
/* #define EDMI_WITH_LG_QUOTIENT EDMI_WITH_LG */
/* The guard: 0 only without GE, PM and PT. */
/* #define EDMI_WITH_GUARD 1 */
/* The potentials, at least one: */
/* #define EDMI_WITH_HARMONIC 1 */
/* #define EDMI_WITH_QUARTIC 1 */
/* #define EDMI_WITH_NEO_HOOKE 1 */
/* #define EDMI_WITH_LJ 1 */
/* #define EDMI_WITH_INVERSE 1 */
/* #define EDMI_WITH_USER 1 */
/* #define EDMI_WITH_CONTACT 1 */
/* edmi_set_field(), edmi_set_force() and edmi_load_scene(): */
/* #define EDMI_WITH_FIELD 1 */
/* #define EDMI_WITH_PORTS 1 */
/* #define EDMI_WITH_SCENE 1 */

/* Port hooks: the square root (default: the compiler builtin, one instruction with an FPU and
 * -fno-math-errno) and an exact fused multiply-add (default: the builtin where the target has
 * the instruction; EDMI_NO_FMA forces the guard's split products, same results). */
/* #define EDMI_SQRT(x) my_sqrtf(x) */
/* #define EDMI_NO_FMA */

#endif /* EDMI_CONFIG_H */
