/**
 * \file edmi.h
 * \brief edmi: energy-decaying, momentum-conserving integrators for particle dynamics.
 *
 * Freestanding C99, no allocation, no stdio, no libm beyond a square root the platform
 * supplies. Implements the five one-step schemes of J. Liu, "On the design of
 * energy-decaying momentum-conserving integrator for nonlinear dynamics using energy
 * splitting and perturbation techniques": implicit mid-point (MP), LaBudde-Greenspan (LG),
 * generalized Eyre (GE), perturbed mid-point (PM) and perturbed trapezoidal (PT), for bodies
 * coupled by pair potentials V(d), bodies tied to anchors and bodies against walls (planes).
 *
 * Read it in this order (README.md has two complete programs and a scene, docs/api.md the
 * API by group):
 *   Configuration    EDMI_REAL, the capacities EDMI_MAX_* and the features EDMI_WITH_*: -D or
 *                    an EDMI_USER_CONFIG file
 *   Types            status codes, parameters, potentials, bodies, links, the system, scenes,
 *                    what a step reports (edmi_step_result), invariants
 *   Build a system   edmi_default_params, edmi_init, edmi_add_*, edmi_set_*, edmi_move_anchor,
 *                    edmi_load_scene, the potential constructors edmi_pot_*
 *   Step it          edmi_step
 *   Measure it       edmi_invariants_of, edmi_pot_eval, edmi_pot_divdiff
 *   Verify it        edmi_residual, edmi_tangent
 *   Misc             edmi_status_name, edmi_is_double_precision, EDMI_CONFIG_MATCHES
 *   (the end)        layouts for sizing only: the workspace's fields, which no caller touches
 *
 * Version 0.2.0.
 * SPDX-License-Identifier: MIT
 * Copyright (c) 2026 the edmi authors. The MIT licence text is in LICENSE; this notice and
 * that text go with every copy of edmi.h and edmi.c.
 */
#ifndef EDMI_H
#define EDMI_H

#define EDMI_VERSION_MAJOR 0
#define EDMI_VERSION_MINOR 2
#define EDMI_VERSION_PATCH 0
/** Packed version: 0xMMmmpp. */
#define EDMI_VERSION ((EDMI_VERSION_MAJOR << 16) | (EDMI_VERSION_MINOR << 8) | EDMI_VERSION_PATCH)

/* ------------------------------------------------------------------------------------------
 * Configuration. Every option can be set with -D or in a file named by EDMI_USER_CONFIG.
 * ---------------------------------------------------------------------------------------- */
#ifdef EDMI_USER_CONFIG
#include EDMI_USER_CONFIG
#endif

/** Floating-point type: float or double. Changes the ABI (see edmi_is_double_precision()). */
#ifndef EDMI_REAL
#define EDMI_REAL double
#endif

/** Bodies per system. Costs 10 reals + 1 int per body in edmi_system (state and force port)
 *  and 32 reals + 6 ints per body in edmi_workspace, plus the Newton matrix (EDMI_MAX_MATRIX). */
#ifndef EDMI_MAX_BODIES
#define EDMI_MAX_BODIES 16
#endif

/** Reals in edmi_workspace's Newton matrix. The matrix of N > 1 bodies is stored by rows of
 *  width W = min(3N, 3 kb + 1) around the diagonal, kb = 3 g + 2 its half-bandwidth and g the
 *  largest body-index gap of a pair link: 3N W reals (the band with its pivoting fill-in).
 *  The default holds the dense matrix of EDMI_MAX_BODIES bodies, so every system fits; a
 *  banded scene can set what its band needs, e.g. 48 N for a chain of N bodies linked to
 *  neighbours (g = 1, W = 16), and an edmi_add_body() or edmi_add_pair() that would not fit
 *  returns EDMI_ERR_CAPACITY (docs/api.md, "Solver"). */
#ifndef EDMI_MAX_MATRIX
#define EDMI_MAX_MATRIX (9 * EDMI_MAX_BODIES * EDMI_MAX_BODIES)
#endif

/** Links (pair or anchor) per system. Costs one edmi_link (2 ints, 5 reals, an enum and 3
 *  pointers, plus padding), 6 reals and an int (moving anchor, link force) in edmi_system
 *  and 56 reals and 4 ints in edmi_workspace per link. */
#ifndef EDMI_MAX_LINKS
#define EDMI_MAX_LINKS 64
#endif

/** Viscous dampers per system (each acts along one link). Costs an int and a real in
 *  edmi_system and 9 reals in edmi_workspace per damper. 0 compiles dampers out: the step
 *  holds no damper code (edmi_add_damper() then returns EDMI_ERR_DISABLED) and the structs
 *  keep one unused slot. */
#ifndef EDMI_MAX_DAMPERS
#define EDMI_MAX_DAMPERS 16
#endif

/** Walls per system: a body against a plane, V(g) of its gap g = n.q - c (edmi_add_wall()).
 *  Costs an edmi_wall and 3 reals (its force) in edmi_system and an edmi_link_ws in
 *  edmi_workspace per wall, and the wall's next offset (296 B in float on a 32-bit core), and an
 *  int. 0 (the default) compiles walls out: the step holds no wall code, the structs no wall
 *  members (sys->n_walls, wall[], wall_force[] exist only with walls), and edmi_add_wall()
 *  and edmi_move_wall() return EDMI_ERR_DISABLED. */
#ifndef EDMI_MAX_WALLS
#define EDMI_MAX_WALLS 0
#endif

/** Coupled masses (the paper's general mass matrix M, section 2): the largest body-index gap
 *  |a - b| of an off-diagonal entry m_ab that edmi_set_mass_coupling() may set, e.g. 1 for a
 *  chain of bar elements with a consistent mass matrix. Costs EDMI_MAX_MASS_GAP reals per body
 *  in edmi_system. 0 (the default) compiles coupled masses out: M is diagonal (one mass per
 *  body) and a build pays nothing for the option. */
#ifndef EDMI_MAX_MASS_GAP
#define EDMI_MAX_MASS_GAP 0
#endif

/** Features. Each EDMI_WITH_* is 1 by default; 0 compiles the feature out of edmi.c (its
 *  code and its branches in the step), and a call that would use it returns
 *  EDMI_ERR_DISABLED with nothing changed. The flash each saves on the Cortex-M4F (float,
 *  -Os) and the configurations `make cross` builds and tests: docs/sizing.md, "Build options".
 *  The schemes (at least one): a guarded scheme (GE, PM, PT) always carries the guard. */
#ifndef EDMI_WITH_MP
#define EDMI_WITH_MP 1
#endif
#ifndef EDMI_WITH_LG
#define EDMI_WITH_LG 1
#endif
#ifndef EDMI_WITH_GE
#define EDMI_WITH_GE 1
#endif
#ifndef EDMI_WITH_PM
#define EDMI_WITH_PM 1
#endif
#ifndef EDMI_WITH_PT
#define EDMI_WITH_PT 1
#endif
/** The passivity guard (docs/energy-safe.md). A guarded scheme (GE, PM, PT) always carries
 *  it: 0 is allowed only in a build of MP and LG alone, where EDMI_GUARD_ON is then refused. */
#ifndef EDMI_WITH_GUARD
#define EDMI_WITH_GUARD 1
#endif
/** LG's quotient form (EDMI_LG_QUOTIENT, also LG's form for a user potential without a
 *  divided difference) with its alternate forces; with LG, EDMI_LG_CLOSED stays. */
#ifndef EDMI_WITH_LG_QUOTIENT
#define EDMI_WITH_LG_QUOTIENT EDMI_WITH_LG
#endif
/** The potentials (at least one): edmi_pot_<name>() still builds a value; a link with a
 *  potential compiled out is refused. */
#ifndef EDMI_WITH_HARMONIC
#define EDMI_WITH_HARMONIC 1
#endif
#ifndef EDMI_WITH_QUARTIC
#define EDMI_WITH_QUARTIC 1
#endif
#ifndef EDMI_WITH_NEO_HOOKE
#define EDMI_WITH_NEO_HOOKE 1
#endif
#ifndef EDMI_WITH_LJ
#define EDMI_WITH_LJ 1
#endif
#ifndef EDMI_WITH_INVERSE
#define EDMI_WITH_INVERSE 1
#endif
#ifndef EDMI_WITH_USER
#define EDMI_WITH_USER 1
#endif
/** The one-sided (contact) potentials EDMI_POT_CONTACT and EDMI_POT_TETHER, one option. */
#ifndef EDMI_WITH_CONTACT
#define EDMI_WITH_CONTACT 1
#endif
/** The effects beyond links and the loader: edmi_set_field(), edmi_set_force() (the force
 *  ports) and edmi_load_scene(). Moving anchors (edmi_move_anchor()) are always in. */
#ifndef EDMI_WITH_FIELD
#define EDMI_WITH_FIELD 1
#endif
#ifndef EDMI_WITH_PORTS
#define EDMI_WITH_PORTS 1
#endif
#ifndef EDMI_WITH_SCENE
#define EDMI_WITH_SCENE 1
#endif

/* Capacities the library cannot work with stop the build here, not at run time. The upper
 * bounds keep every index and matrix offset within int (the matrix is indexed up to 9 N^2). */
#if EDMI_MAX_BODIES < 1 || EDMI_MAX_BODIES > 10000
#error "edmi: EDMI_MAX_BODIES must be 1 to 10000"
#endif
#if EDMI_MAX_LINKS < 1 || EDMI_MAX_LINKS > 1000000
#error "edmi: EDMI_MAX_LINKS must be 1 to 1000000 (every body moves under a link)"
#endif
#if EDMI_MAX_DAMPERS < 0 || EDMI_MAX_DAMPERS > 1000000
#error "edmi: EDMI_MAX_DAMPERS must be 0 (dampers compiled out) to 1000000"
#endif
#if EDMI_MAX_WALLS < 0 || EDMI_MAX_WALLS > 1000000
#error "edmi: EDMI_MAX_WALLS must be 0 (walls compiled out) to 1000000"
#endif
#if EDMI_MAX_MASS_GAP < 0 || EDMI_MAX_MASS_GAP >= EDMI_MAX_BODIES
#error "edmi: EDMI_MAX_MASS_GAP must be 0 (diagonal masses) to EDMI_MAX_BODIES - 1"
#endif
#if EDMI_MAX_MATRIX < 9 || EDMI_MAX_MATRIX > 9 * EDMI_MAX_BODIES * EDMI_MAX_BODIES
#error "edmi: EDMI_MAX_MATRIX must be 9 (one body) to 9 * EDMI_MAX_BODIES^2 (dense)"
#endif
#if !(EDMI_WITH_MP || EDMI_WITH_LG || EDMI_WITH_GE || EDMI_WITH_PM || EDMI_WITH_PT)
#error "edmi: at least one scheme EDMI_WITH_MP, _LG, _GE, _PM or _PT must be 1"
#endif
#if !EDMI_WITH_GUARD && (EDMI_WITH_GE || EDMI_WITH_PM || EDMI_WITH_PT)
#error "edmi: GE, PM and PT carry the guard: EDMI_WITH_GUARD = 0 needs them compiled out"
#endif
#if EDMI_WITH_LG_QUOTIENT && !EDMI_WITH_LG
#error "edmi: EDMI_WITH_LG_QUOTIENT needs EDMI_WITH_LG"
#endif
#if !(EDMI_WITH_HARMONIC || EDMI_WITH_QUARTIC || EDMI_WITH_NEO_HOOKE || EDMI_WITH_LJ || \
      EDMI_WITH_INVERSE || EDMI_WITH_USER || EDMI_WITH_CONTACT)
#error "edmi: at least one potential EDMI_WITH_HARMONIC, ... or EDMI_WITH_CONTACT must be 1"
#endif
/* Array length behind EDMI_MAX_DAMPERS: C forbids zero-length arrays. */
#if EDMI_MAX_DAMPERS > 0
#define EDMI_DAMPER_SLOTS_ EDMI_MAX_DAMPERS
#else
#define EDMI_DAMPER_SLOTS_ 1
#endif


/** The port hook: square root of a non-negative edmi_real. The default is the compiler
 *  builtin, which with -fno-math-errno is one instruction (VSQRT.F32 on Cortex-M4F, VSQRT.F64
 *  on M7, SQRTSD on x86-64); on a core without an FPU it becomes a call to sqrtf/sqrt that
 *  the C library or port/ supplies. */
#ifndef EDMI_SQRT
#if defined(__GNUC__) || defined(__clang__)
#define EDMI_SQRT(x) EDMI_SQRT_BUILTIN_(x)
#else
#error "edmi: define EDMI_SQRT(x) for this compiler (docs/porting.md)"
#endif
#endif

/** Port hook (optional): EDMI_FMA(a, b, c) = a * b + c rounded once, a fused multiply-add.
 *  The passivity guard uses it for exact products. Default: the compiler builtin where the
 *  target has the instruction (GCC and Clang announce it with __FP_FAST_FMAF and
 *  __FP_FAST_FMA: VFMA.F32 on a Cortex-M4F, VFMA.F64 on an M7); elsewhere (Cortex-M0+,
 *  rv32imac, x86-64 without -mfma) none, and the guard splits its operands instead
 *  (Veltkamp and Dekker: 17 operations per product, no library call). Define EDMI_NO_FMA to
 *  force the split. Both give exact products, so results are identical. Costs nothing else. */
#if !defined(EDMI_FMA) && !defined(EDMI_NO_FMA)
#define EDMI_FMA_DEFAULT_ 1
#endif

#include <float.h>
#include <limits.h>
#if INT_MAX < 2147483647
#error "edmi: needs an int of at least 32 bits (matrix offsets reach 9 * EDMI_MAX_BODIES^2)"
#endif

#ifdef __cplusplus
extern "C" {
#endif

/* ------------------------------------------------------------------------------------------
 * Types
 * ---------------------------------------------------------------------------------------- */

/** The library's real type. */
typedef EDMI_REAL edmi_real;

/* Literal, epsilon and builtin sqrt in the configured precision, so that a float build
 * contains no double arithmetic. EDMI_R(1.5) is 1.5f in a float build. */
#define EDMI_FLOAT_ 1
#define EDMI_DOUBLE_ 2
#define EDMI_PREC_float EDMI_FLOAT_
#define EDMI_PREC_double EDMI_DOUBLE_
#define EDMI_PREC_X_(t) EDMI_PREC_##t
#define EDMI_PREC_(t) EDMI_PREC_X_(t)
#if EDMI_PREC_(EDMI_REAL) == EDMI_FLOAT_
#define EDMI_R(x) x##f
#define EDMI_EPS FLT_EPSILON
#define EDMI_REAL_MAX FLT_MAX
#define EDMI_SQRT_BUILTIN_(x) __builtin_sqrtf(x)
#elif EDMI_PREC_(EDMI_REAL) == EDMI_DOUBLE_
#define EDMI_R(x) x
#define EDMI_EPS DBL_EPSILON
#define EDMI_REAL_MAX DBL_MAX
#define EDMI_SQRT_BUILTIN_(x) __builtin_sqrt(x)
#else
#error "edmi: EDMI_REAL must be float or double"
#endif
/* The guard's exact arithmetic assumes IEEE binary32 and binary64 (AVR's double, for one, is
 * 32 bits: use float there). */
#if EDMI_PREC_(EDMI_REAL) == EDMI_FLOAT_ && (FLT_RADIX != 2 || FLT_MANT_DIG != 24)
#error "edmi: EDMI_REAL float needs an IEEE binary32 float"
#elif EDMI_PREC_(EDMI_REAL) == EDMI_DOUBLE_ && (FLT_RADIX != 2 || DBL_MANT_DIG != 53)
#error "edmi: EDMI_REAL double needs an IEEE binary64 double; this target's is narrower (use float)"
#endif
#if defined(EDMI_FMA_DEFAULT_) && EDMI_PREC_(EDMI_REAL) == EDMI_FLOAT_ && defined(__FP_FAST_FMAF)
#define EDMI_FMA(a, b, c) __builtin_fmaf(a, b, c)
#elif defined(EDMI_FMA_DEFAULT_) && EDMI_PREC_(EDMI_REAL) == EDMI_DOUBLE_ && defined(__FP_FAST_FMA)
#define EDMI_FMA(a, b, c) __builtin_fma(a, b, c)
#endif

/** Status of every call that can fail. A call that returns anything but EDMI_OK has left the
 *  system (and every output except the step result) bit-identical to before the call. */
typedef enum edmi_status {
    EDMI_OK = 0,
    EDMI_ERR_NULL,           /*!< a required pointer is NULL */
    EDMI_ERR_DT,             /*!< dt <= 0 or not finite */
    EDMI_ERR_MASS,           /*!< a mass <= 0 or not finite */
    EDMI_ERR_NONFINITE,      /*!< a position, momentum, anchor or parameter is not finite */
    EDMI_ERR_CAPACITY,       /*!< a capacity (EDMI_MAX_BODIES, _LINKS, _DAMPERS, _WALLS, the
                                  Newton matrix's EDMI_MAX_MATRIX) would be exceeded */
    EDMI_ERR_INDEX,          /*!< a body index is out of range, or a link ties a body to itself */
    EDMI_ERR_PARAM,          /*!< an invalid potential parameter, scheme, option or tolerance */
    EDMI_ERR_COINCIDENT,     /*!< two linked bodies (or a body and its anchor) at distance 0 */
    EDMI_ERR_SINGULAR,       /*!< the Newton matrix is singular to working precision */
    EDMI_ERR_NO_CONVERGENCE, /*!< Newton did not meet tol_r/tol_a within l_max iterations */
    EDMI_ERR_DIVERGED,       /*!< Newton's iterates left the potentials' domain (a distance
                                  0, a user callback refusing, a residual not finite) and
                                  halving the correction did not bring them back within l_max
                                  iterations */
    EDMI_ERR_PASSIVITY,      /*!< the guard could not certify H_n+1 - H_n <= work + what the
                                  energy tank holds (values beyond the range its double-word
                                  arithmetic covers, or an excess larger than the kinetic
                                  energy it may remove) */
    EDMI_ERR_RANGE,          /*!< an input refused: every value is finite, but the start
                                  state's potentials (a link's or wall's V or V') are beyond
                                  the precision's range there (docs/api.md, "Limits") */
    EDMI_ERR_DISABLED,       /*!< a scheme, potential, LG form or effect this build compiled
                                  out (an EDMI_WITH_* option set to 0, or a damper or wall
                                  where EDMI_MAX_DAMPERS or EDMI_MAX_WALLS is 0); checked after
                                  the pointers, counts and values: an invalid potential of a
                                  kind compiled out is EDMI_ERR_PARAM */
    EDMI_ERR_UNINIT,         /*!< a builder (edmi_add_*) was given a system that edmi_init()
                                  or edmi_load_scene() did not set up: its params are not
                                  valid */
    EDMI_ERR_CORRUPT,        /*!< a count in sys (n_bodies, n_links, n_dampers, n_walls, or
                                  one of sys->internal) is out of range: the caller overwrote
                                  it. Every call that reads sys checks the counts first */
    EDMI_ERR_OVERFLOW,       /*!< a result is beyond the precision's range although every
                                  input was accepted: in a step its scale (|q| + dt |p| / m),
                                  residual, work, energy balance or a force (the step failed:
                                  substeps and the fallback take it over); in a query the value
                                  asked for (an invariant, a potential's derivative, a tangent
                                  block) */
    EDMI_ERR_END_STATE,      /*!< Newton solved the step, but its solution ends a link or wall
                                  where the next step could not start: at length 0 with a
                                  potential undefined there, outside a user potential's
                                  domain, or where V or V' is beyond the range (MP and LG's
                                  alternates never evaluate V at the end). A failed step:
                                  substeps and the fallback take it over */
    EDMI_ERR_DOMAIN          /*!< a distance outside a potential's domain: a user callback
                                  refused it (at the start state a step is given, or in
                                  edmi_pot_eval(), edmi_pot_divdiff()), or a trial state given
                                  to edmi_residual() or edmi_tangent() puts a link (or its
                                  mid-point) at length 0 or where a user callback refuses */
} edmi_status;

/** The five algorithmic forces of the paper (section 4.1). */
typedef enum edmi_scheme {
    EDMI_SCHEME_MP = 0, /*!< implicit mid-point, f_mp: V' at the distance between the
                             mid-points */
    EDMI_SCHEME_LG, /*!< LaBudde-Greenspan, f_lg: energy-conserving */
    EDMI_SCHEME_GE, /*!< generalized Eyre, f_ge: convex/concave split, 1st order, decaying */
    EDMI_SCHEME_PM, /*!< perturbed mid-point, f_pm: super-convex/concave, 2nd order, decaying */
    EDMI_SCHEME_PT  /*!< perturbed trapezoidal, f_pt: super-convex/concave, 2nd order,
                         decaying */
} edmi_scheme;

/** How LG evaluates its difference quotient [V(d1)-V(d0)]/(d1-d0). */
typedef enum edmi_lg_form {
    /** Closed-form divided difference (never divides by d1-d0; the paper's eq. solar_flg_2
     *  generalised to every built-in potential): no switch, energy conserved to round-off.
     *  Default. A user potential without a divided-difference callback falls back to
     *  EDMI_LG_QUOTIENT. */
    EDMI_LG_CLOSED = 0,
    /** The quotient as written, replaced by the alternate force of edmi_lg_alt on every link
     *  whose |d1 - d0| <= params.tol_q (the paper's section 3.4). */
    EDMI_LG_QUOTIENT
} edmi_lg_form;

/** LG's alternate force on a link when |d1 - d0| <= params.tol_q (EDMI_LG_QUOTIENT only). */
typedef enum edmi_lg_alt {
    EDMI_LG_ALT_JANZ = 0, /*!< V'(d_avg), the paper's default (eq. janz-mid-point-rescue) */
    EDMI_LG_ALT_GONZALEZ, /*!< V'(d_avg) + (d1-d0)^2/24 V'''(d_avg)
                               (eq. gonzalez-mid-point-rescue) */
    EDMI_LG_ALT_GE,       /*!< the generalized Eyre force: energy-decaying */
    EDMI_LG_ALT_PM,       /*!< the perturbed mid-point force: energy-decaying */
    EDMI_LG_ALT_PT        /*!< the perturbed trapezoidal force: energy-decaying */
} edmi_lg_alt;

/** The passivity guard (docs/energy-safe.md). */
typedef enum edmi_guard_mode {
    EDMI_GUARD_AUTO = 0, /*!< on for the energy-decaying schemes GE, PM, PT; off for MP, LG */
    EDMI_GUARD_ON,       /*!< on for every scheme (MP and LG then never gain energy either) */
    EDMI_GUARD_OFF       /*!< off: the step stores Newton's iterate as it is (for studies) */
} edmi_guard_mode;

/** Solver and scheme parameters; start from edmi_default_params() and edit. */
typedef struct edmi_params {
    edmi_scheme scheme;  /*!< which algorithmic force */
    edmi_lg_form lg_form; /*!< LG only: closed-form divided difference or quotient + switch */
    edmi_lg_alt lg_alt;  /*!< LG quotient only: alternate force in the singular limit */
    edmi_real tol_q;     /*!< LG quotient only: switch when |d1 - d0| <= tol_q [length] */
    edmi_real tol_r;     /*!< optional early stop: scaled residual <= tol_r * scaled residual
                              of the predictor; 0 (default): off, Newton runs to its floor */
    edmi_real tol_a;     /*!< optional early stop: scaled residual <= tol_a; 0 (default): off */
    int l_max;           /*!< at most this many Newton corrections per step (>= 1), plus
                              one chord correction from the factors the system's last step
                              kept (edmi_workspace) where it does not halve the residual */
    int energy_balance;  /*!< non-zero: edmi_step reports dh and diss_scheme in double-word
                              arithmetic on every step, guard on or off (costs a double-word
                              evaluation of H per step); 0 by default */
    edmi_guard_mode guard; /*!< passivity guard: H_n+1 - H_n <= work + T_n - T_n+1 on the
                              stored values, T the energy tank (edmi_system.tank) */
    edmi_real tank_cap;  /*!< the energy tank's capacity in units of EDMI_EPS times the
                              magnitude of H's terms at the step's end (res.tank_cap): over any
                              window of steps H rises by at most the work plus the tank's
                              level at its start. 256 by default; 0 is the per-step guarantee
                              H_n+1 - H_n <= work: a step neither spends a tank (whatever
                              sys.tank holds) nor keeps one, T_n+1 = 0 (docs/energy-safe.md) */
    int substep_levels;  /*!< k in 0..EDMI_MAX_SUBSTEP_LEVELS: a step that fails after its
                              input was accepted (Newton: singular, l_max reached, diverged;
                              the guard; a result beyond the range) is taken again as two
                              substeps of dt/2, a substep that fails as two of half its size,
                              down to dt/2^k, within the same call; the substeps' passivity
                              and energy balances add up to the step's (res.substeps).
                              At most 2^(k+1) - 1 Newton solves per call. 0 by default */
    int fallback;        /*!< non-zero: where a step (or, with substep_levels, a substep of
                              dt/2^k) still fails, the call stores a passive fallback state
                              instead of failing and returns EDMI_OK, stop
                              EDMI_STOP_FALLBACK, res.cause the failure: with the guard on,
                              Newton's last iterate when it got closer than the predictor,
                              made passive by the guard (the motion goes on); else the
                              positions kept and the kinetic energy relative to the centre of
                              mass (with anchors, all of it) removed. With fallback, every
                              step whose input edmi_step() accepts returns EDMI_OK in bounded
                              time (docs/targets.md counts it); the one exception is an
                              anchor moved (edmi_move_anchor()) onto its body or beyond the
                              range, where no passive state exists. 0 by default */
} edmi_params;

/** The largest edmi_params.substep_levels: 2^10 substeps. */
#define EDMI_MAX_SUBSTEP_LEVELS 10

/** Derivatives 0..4 of the split parts of a potential at one distance r:
 *  V = c + e (convex/concave: c'' >= 0, e'' <= 0) and V = sp + sm
 *  (super-convex/super-concave: sp'''' >= 0, sm'''' <= 0). Index k holds the k-th derivative. */
typedef struct edmi_pot_parts {
    edmi_real v[5];  /*!< V itself, in its best-conditioned form (for built-ins not computed
                          as c + e, which cancels near a rest length); user potentials: c + e */
    edmi_real c[5];  /*!< convex part V_c */
    edmi_real e[5];  /*!< concave part V_e */
    edmi_real sp[5]; /*!< super-convex part V_+ */
    edmi_real sm[5]; /*!< super-concave part V_- */
} edmi_pot_parts;

/** User potential: fill c, e, sp, sm of *out at distance r > 0 (v is set to c + e). Return 0
 *  on success, non-zero if r is outside the potential's domain: a step's start there is
 *  refused with EDMI_ERR_DOMAIN, a Newton iterate there is halved back (EDMI_ERR_DIVERGED if
 *  it stays), a solution ending there fails with EDMI_ERR_END_STATE. */
typedef int (*edmi_user_pot_fn)(void *ctx, edmi_real r, edmi_pot_parts *out);

/** Optional user divided difference: *dd = [V(d1)-V(d0)]/(d1-d0) and
 *  *dd_d1 = d(dd)/d(d1), both in a form that stays finite at d1 == d0. Return 0 on success. */
typedef int (*edmi_user_dd_fn)(void *ctx, edmi_real d0, edmi_real d1, edmi_real *dd,
                               edmi_real *dd_d1);

/** Built-in potentials (section 3.1 of the paper). */
typedef enum edmi_pot_kind {
    EDMI_POT_HARMONIC = 0, /*!< V = k/2 (r - r0)^2;              a = k > 0, b = r0 >= 0 */
    EDMI_POT_QUARTIC,      /*!< V = k/4 (r^2 - L^2)^2 (Gonzalez); a = k > 0, b = L >= 0 */
    EDMI_POT_NEO_HOOKE,    /*!< V = c rb^2/6 ((r/rb)^2 + 2 rb/r - 3); a = c > 0, b = rb > 0 */
    EDMI_POT_LJ,           /*!< V = 4 eps ((s/r)^12 - (s/r)^6);  a = eps > 0, b = s > 0 */
    EDMI_POT_INVERSE,      /*!< V = -k/r (gravity k = G m_A m_B > 0, Coulomb k < 0); a = k != 0 */
    EDMI_POT_USER,         /*!< callbacks fn (required) and dd (optional) with ctx */
    EDMI_POT_CONTACT,      /*!< compression only: V = k/3 (R - r)^3 for r < R, else 0 (two balls
                                whose radii add to R, a ball about an anchor); a = k > 0, b = R > 0 */
    EDMI_POT_TETHER        /*!< tension only: V = k/3 (r - L)^3 for r > L, else 0 (a slack rope
                                of length L, a body kept within a sphere); a = k > 0, b = L >= 0 */
} edmi_pot_kind;

/** A pair potential. Build it with edmi_pot_harmonic() etc. */
typedef struct edmi_potential {
    edmi_pot_kind kind;
    edmi_real a;         /*!< first parameter (see edmi_pot_kind) */
    edmi_real b;         /*!< second parameter (see edmi_pot_kind) */
    edmi_user_pot_fn fn; /*!< EDMI_POT_USER: derivatives of the split parts */
    edmi_user_dd_fn dd;  /*!< EDMI_POT_USER: closed-form divided difference, or NULL */
    void *ctx;           /*!< EDMI_POT_USER: passed to fn and dd */
} edmi_potential;

/** A body: diagonal mass, position and momentum.
 *
 *  State access: between edmi_step() calls the caller may read and write sys.body[i].q, .p
 *  and .m directly (a tracked object's position, a reset, a new load). The next edmi_step()
 *  checks them (non-finite: EDMI_ERR_NONFINITE; m <= 0: EDMI_ERR_MASS; the system unchanged)
 *  and starts from them exactly as a system built with that state would: nothing about a
 *  body is cached between steps. Energy put in or taken out by such a write is not in any
 *  step's energy balance and not bounded by the guard, which holds from the written state
 *  on. Never write during an edmi_step() call (edmi keeps no locks), and add bodies, links
 *  and dampers only through edmi_add_*() or edmi_load_scene(). */
typedef struct edmi_body {
    edmi_real m;    /*!< mass [M] */
    edmi_real q[3]; /*!< position [L] */
    edmi_real p[3]; /*!< linear momentum [M L / T] */
} edmi_body;

/** Marks a link whose second end is a fixed anchor point. */
#define EDMI_ANCHOR (-1)

/** A link: potential V(d) between bodies a and b, or between body a and a fixed anchor. */
typedef struct edmi_link {
    int a;               /*!< first body */
    int b;               /*!< second body, or EDMI_ANCHOR */
    edmi_real anchor[3]; /*!< anchor point [L] when b == EDMI_ANCHOR (else zero) */
    edmi_potential pot;  /*!< the pair potential */
} edmi_link;

/** A linear viscous damper along a link's two ends (or its body and anchor). */
typedef struct edmi_damper {
    int link;    /*!< the link whose ends it joins */
    edmi_real c; /*!< damping coefficient >= 0 [M / T]: force = c * relative speed along the link */
} edmi_damper;

/** A wall: body a against the plane n.x = c, with the potential V(g) of its gap g = n.q_a - c
 *  (> 0 on the side n points to). Its force -V'(g) n (each scheme's discrete form) is along
 *  n: the momentum along the plane and the angular momentum about any axis along n are kept.
 *  The potentials a wall takes: edmi_pot_contact(k, R), V = k/3 (R - g)^3 below g = R (a ball
 *  of radius R >= 0 against a rigid floor), edmi_pot_tether(k, L), V = k/3 (g - L)^3 beyond
 *  g = L (a body kept within L of the plane), and edmi_pot_harmonic(k, g0), k/2 (g - g0)^2. */
typedef struct edmi_wall {
    int a;               /*!< the body */
    edmi_real n[3];      /*!< unit normal, as edmi_add_wall() stored it (normalised) */
    edmi_real c;         /*!< the plane's offset along n [L] */
    edmi_potential pot;  /*!< V of the gap; its b (R, L or g0) may be 0 */
} edmi_wall;

/** An off-diagonal entry m_ab = m_ba of the mass matrix (edmi_set_mass_coupling()). */
typedef struct edmi_mass_coupling {
    int a, b;    /*!< two different bodies, |a - b| <= EDMI_MAX_MASS_GAP */
    edmi_real m; /*!< m_ab [M] */
} edmi_mass_coupling;

/** A system: bodies, links, parameters and time. Caller-owned; initialise with edmi_init()
 *  (or edmi_load_scene()), then add to it with edmi_add_*() and edmi_set_*(). Its fields come
 *  in four groups:
 *  - the state the caller may write between steps: body[] (edmi_body says how), t and params;
 *    the next edmi_step() checks them;
 *  - what the builders set, to read: the counts, link[], the effects, tank (change them only
 *    through the calls named at each);
 *  - the outputs of the last successful step: link_force, wall_force;
 *  - internal: the library's own bookkeeping between calls. Treat it as opaque: edmi.c alone
 *    reads and writes it, and its members may change in any release. */
typedef struct edmi_system {
    int n_bodies;
    int n_links;
    edmi_real t;       /*!< time of the current state [T], advanced by edmi_step() */
    edmi_params params;
    edmi_body body[EDMI_MAX_BODIES];
    edmi_link link[EDMI_MAX_LINKS];
    /* Effects beyond links; each is a list, so an absent effect costs nothing in a step. */
    int has_field;                       /*!< uniform field set by edmi_set_field() */
    edmi_real g[3];                      /*!< field acceleration: force m g on every body [L/T^2] */
    int n_dampers;
    edmi_damper damper[EDMI_DAMPER_SLOTS_];
#if EDMI_MAX_WALLS > 0
    int n_walls;
    edmi_wall wall[EDMI_MAX_WALLS];      /*!< edmi_add_wall(); c moves with edmi_move_wall() */
#endif
    edmi_real force[EDMI_MAX_BODIES][3]; /*!< port force per body, edmi_set_force() [M L/T^2] */
#if EDMI_MAX_MASS_GAP > 0
    /** The mass matrix's off-diagonal band (edmi_set_mass_coupling()): mass_off[a][k] is
     *  m_ab = m_ba for b = a - 1 - k [M]; 0 where bodies are not coupled. The diagonal is
     *  body[a].m. M must stay symmetric positive definite: edmi_step() checks it. */
    edmi_real mass_off[EDMI_MAX_BODIES][EDMI_MAX_MASS_GAP];
#endif
    /** The energy tank T_n [energy]: with the guard on, every step stores a state with
     *  H_n+1 - H_n <= work + T_n - T_n+1 exactly, and 0 <= T_n+1 <= res.tank_cap, so that
     *  T_n <= (the work supplied since T was 0) - (H_n - H at that time). 0 after edmi_init()
     *  and edmi_load_scene(); read it, save and restore it with the bodies, or empty it, with
     *  edmi_set_tank(). Untouched by steps with the guard off; with params.tank_cap 0 a step
     *  neither spends it nor keeps one (T_n+1 = 0). */
    edmi_real tank;
    /** Output of the last successful step: the mean force link j applied on its second end
     *  (body b, or the anchor: the force a motor renders to a hand) over the step, its
     *  algorithmic force plus its dampers [M L/T^2]. The work the anchors did on the system
     *  is -sum link_force . (x_n+1 - x_n), reported as edmi_step_result.work_anchor. */
    edmi_real link_force[EDMI_MAX_LINKS][3];
#if EDMI_MAX_WALLS > 0
    /** Output of the last successful step: the mean force wall w took from its body over the
     *  step, V'(g) n in the scheme's discrete form [M L/T^2] (the body felt its opposite). */
    edmi_real wall_force[EDMI_MAX_WALLS][3];
#endif
    /** Internal: opaque to the caller (see above). */
    struct edmi_system_internal_ {
        /* Where the factors of the last step's Newton matrix are kept: the workspace, that
         * step's dt and sizes (edmi_step). The next step with the same workspace and dt
         * starts Newton from them. */
        const void *kept_work;
        edmi_real kept_dt;
        edmi_real t_carry; /* compensated-summation remainder of t (C(t) depends on t: a
                              plain t += dt drifts by ~n eps t after n steps) */
#if EDMI_MAX_WALLS > 0
        edmi_real wall_next[EDMI_MAX_WALLS]; /* each wall's offset c at the end of the next
                                                step (edmi_move_wall(); c when it rests) [L] */
#endif
        edmi_real anchor_next[EDMI_MAX_LINKS][3]; /* where each moving anchor reaches at the
                                                     end of the next step [L] */
        int kept_bodies, kept_links;
        int n_forced;                /* bodies with a port force set (edmi_set_force()) */
        int forced[EDMI_MAX_BODIES]; /* their indices */
        int n_moving;                /* anchor links moved by edmi_move_anchor() */
        int moving[EDMI_MAX_LINKS];  /* their link indices */
    } internal;
} edmi_system;


/** A scene as plain constant data (it can live in flash): the bodies, links and dampers
 *  a system starts from, its field and parameters. Load it with edmi_load_scene(). */
typedef struct edmi_scene {
    int n_bodies;
    const edmi_body *bodies;     /*!< n_bodies initial states */
    int n_links;
    const edmi_link *links;      /*!< n_links links (anchor links have b == EDMI_ANCHOR) */
    int n_dampers;
    const edmi_damper *dampers;  /*!< n_dampers dampers (may be NULL when 0) */
    int has_field;               /*!< non-zero: uniform field g */
    edmi_real g[3];              /*!< field acceleration [L/T^2] */
    const edmi_params *params;   /*!< parameters, or NULL for edmi_default_params() */
    int n_mass_couplings;        /*!< off-diagonal masses (0 for one mass per body) */
    const edmi_mass_coupling *mass_couplings; /*!< each pair at most once (may be NULL when 0) */
} edmi_scene; /* walls are added after loading, with edmi_add_wall() */

/** Newton's workspace. Caller-owned; one workspace may serve several systems stepped one
 *  after another. Between calls it keeps what the next step of the system it last served may
 *  reuse: the factors of that step's Newton matrix, which the next edmi_step() with the same
 *  dt uses for its first corrections (the system records where they are), and the links'
 *  potential values at the step's end, reused only where a link's ends and potential are
 *  bit for bit the ones they were evaluated for. The same calls give the same results on
 *  every target; a step's last bits can depend on whether the workspace served another
 *  system since. */
typedef struct edmi_workspace edmi_workspace; /* its layout: at the end of this header */

/** Why Newton stopped (a successful step). Every stop but EDMI_STOP_FALLBACK leaves an
 *  iterate that solves the scheme's equations body by body to the bound EDMI_SOLVED (below):
 *  EDMI_OK means solved. */
typedef enum edmi_stop {
    EDMI_STOP_CONVERGED = 0, /*!< at the round-off floor: the next Newton correction,
                                  predicted from the last two in the quadratic regime
                                  (c_l^3 / c_l-1^2, with c_l <= c_l-1 / 4 and a residual
                                  below sqrt(eps) x residual0), is below eps in the scaled
                                  norm, so it could not move the iterate by a unit roundoff;
                                  or a correction or the residual is exactly 0 (a correction
                                  of 0 short of EDMI_SOLVED: EDMI_ERR_NO_CONVERGENCE) */
    EDMI_STOP_STALLED,   /*!< round-off noise above eps: the residual stopped halving (and
                              did not more than double) after Newton's quadratic regime (this
                              and the previous residual both <= sqrt(eps) x residual0), or
                              stopped halving within 8x its round-off noise as
                              estimated from the magnitudes summed into it (the potentials'
                              cancelling terms, the LG quotient's eps |V| / |d1 - d0|) */
    EDMI_STOP_TOL_R,     /*!< scaled residual <= tol_r * initial scaled residual (tol_r > 0),
                              and the bound below with EDMI_SOLVED EDMI_EPS raised to tol_r */
    EDMI_STOP_TOL_A,     /*!< scaled residual <= tol_a (tol_a > 0), and the bound below with
                              EDMI_SOLVED EDMI_EPS raised to tol_a */
    EDMI_STOP_FALLBACK   /*!< params.fallback: the step (or a substep) failed and stored the
                              fallback state (res.cause says why): passive, not solved */
} edmi_stop;

/** What EDMI_OK means: Newton's iterate (q1, p1), the stored state before the guard's moves
 *  (edmi_step_result.guard_action), satisfies, for every body a,
 *      |R_q,a| <= EDMI_SOLVED EDMI_EPS Q_a,   |R_p,a| <= EDMI_SOLVED EDMI_EPS P_a,
 *  R_q, R_p the scheme's residuals (edmi_residual()) and |.| the Euclidean norm, with the
 *  magnitudes of the terms summed into them, taken at the step's two ends:
 *      Q_a = |q_n| + |q1| + dt/m_a (|p_n| + |p1|)  [+ |m_ab| / m_a (|q_n,b| + |q1_b|)],
 *      P_a = |p_n| + |p1| + dt |F_a| + dt |m_a g|
 *            + sum over a's links of 4 (dt |f| + 3 k (|r_m| + Q_a + Q_b)) + cancellation
 *            + sum over a's dampers of 4 c (|r_n| + |r1| + Q_a + Q_b),
 *  f the link's force at its mid-point vector r_m, k the largest entry of its tangent block
 *  dt df/dr_n+1, Q_b = |x_n+1| for an anchor, "cancellation" the potential's cancelling
 *  terms (the LG quotient's |V| / |d1 - d0|), and 16 EDMI_EPS times the smallest normal
 *  added to each (the subnormal grid). The bound holds however large the terms are: a step
 *  whose residual Newton leaves above it fails with EDMI_ERR_NO_CONVERGENCE (or takes the
 *  fallback), never EDMI_OK. Its stiffness term 3 k Q is what moving a position by its unit in
 *  the last place changes R_p by, the floor of any state on the grid: where that exceeds the
 *  forces (a body a few units from a repulsive wall's centre, moving less than a unit in the
 *  step), EDMI_OK means solved to the grid's resolution only, the positions within a unit of
 *  the scheme's solution and |R_p| up to the size of dt |f| (docs/api.md, "Limits"). */
#define EDMI_SOLVED 1024

/** Bits of edmi_step_result.guard_action: what the passivity guard changed. */
#define EDMI_MOVE_IMPULSE 1u /*!< an impulse along one link (keeps L, J, C; an anchor link
                                  keeps J about its anchor) moved H towards its target */
#define EDMI_MOVE_DRAG 2u    /*!< a drag relative to the centre of mass (keeps L, not J):
                                  no link could remove the excess */
#define EDMI_MOVE_ROUND 4u   /*!< momentum components moved by a few units in the last place
                                  (the energy-aware rounding of the stored state) */
#define EDMI_MOVE_STOP 8u    /*!< at the bottom of the range (every energy below ~2^-54 of a
                                  unit in float, 2^-863 in double: a system come to rest),
                                  where the grid is too coarse for the moves above: positions
                                  kept and momenta set to the frame's, as the fallback state */
#define EDMI_MOVE_HOLD 16u   /*!< no position moved and the tank could not cover the momenta's
                                  rise: the step kept the state it started from (H and the
                                  works unchanged exactly; a body held at rest by the grid a
                                  few units in the last place off an anchor) */

/* The names before 0.2.0 (one prefix per enum since), kept so that a caller written for 0.1
 * still compiles; define EDMI_NO_OLD_NAMES to drop them. The statuses split in 0.2.0 have no
 * such alias: EDMI_ERR_RANGE, _DIVERGED and _CAPACITY each lost a meaning (edmi_status). */
#ifndef EDMI_NO_OLD_NAMES
#define EDMI_MP EDMI_SCHEME_MP
#define EDMI_LG EDMI_SCHEME_LG
#define EDMI_GE EDMI_SCHEME_GE
#define EDMI_PM EDMI_SCHEME_PM
#define EDMI_PT EDMI_SCHEME_PT
#define EDMI_ALT_JANZ EDMI_LG_ALT_JANZ
#define EDMI_ALT_GONZALEZ EDMI_LG_ALT_GONZALEZ
#define EDMI_ALT_GE EDMI_LG_ALT_GE
#define EDMI_ALT_PM EDMI_LG_ALT_PM
#define EDMI_ALT_PT EDMI_LG_ALT_PT
#define EDMI_GUARD_IMPULSE EDMI_MOVE_IMPULSE
#define EDMI_GUARD_DRAG EDMI_MOVE_DRAG
#define EDMI_GUARD_ROUND EDMI_MOVE_ROUND
#define EDMI_GUARD_STOP EDMI_MOVE_STOP
#define EDMI_GUARD_HOLD EDMI_MOVE_HOLD
#endif

/** How a step's energy change was certified (edmi_step_result.certificate). */
typedef enum edmi_certificate {
    EDMI_CERT_NONE = 0,   /*!< not evaluated (guard off, no energy_balance, or a failed step),
                               or a fallback state passive by construction (momenta 0,
                               positions kept, work_anchor an upper bound of V's change) */
    EDMI_CERT_PLAIN,      /*!< working precision with an a-priori error bound: the step
                               dissipated more than the bound and the tank stays full */
    EDMI_CERT_DOUBLE_WORD, /*!< double-word arithmetic, error ~ EDMI_EPS^2 of H's terms */
    EDMI_CERT_SCALED      /*!< double-word on values scaled by a power of two: energies
                               near the bottom of the range (a system coming to rest) */
} edmi_certificate;

/** What one step did. Filled on success and on the failures after the input was accepted
 *  (so the caller can see how far Newton got); zeroed on input errors. */
typedef struct edmi_step_result {
    int iterations;      /*!< Newton corrections taken */
    edmi_stop stop;      /*!< why Newton stopped (meaningful when the step succeeded) */
    edmi_real residual;  /*!< final scaled residual of Newton's iterate (dimensionless, see
                              docs/api.md; before the guard's rounding of the stored state) */
    edmi_real residual0; /*!< scaled residual of the predictor */
    edmi_real correction; /*!< last Newton correction in the same scaled norm */
    int lg_switches;     /*!< LG quotient: links evaluated with the alternate force, last iterate */
    int halvings;        /*!< halvings of Newton corrections that left the potentials' domain
                              (a link distance 0 or a non-finite residual) */
    /* The discrete energy balance of the stored states,
     *     H_n+1 - H_n = work_ext + work_anchor - diss_scheme - diss_damping - diss_guard,
     * exact up to the Newton residual. With the guard on, H_n+1 - H_n <= work_ext +
     * work_anchor + T_n - T_n+1 holds exactly for the stored values and the tank
     * (docs/energy-safe.md). */
    edmi_real work_ext;     /*!< work of the force ports, sum F . (q_n+1 - q_n) of the stored
                                 forces and positions, rounded down: never above the exact
                                 value, so that H_n - H_0 <= the exact works' sum + T_0 */
    edmi_real work_anchor;  /*!< work the moving anchors (and walls) did on the system,
                                 -sum link_force . (x_n+1 - x_n) of the stored force and
                                 anchors (a wall's -Lambda (c_n+1 - c_n)), rounded down. A
                                 step taken as substeps reports each work as the substeps'
                                 (each rounded down) summed and rounded down, the unit that
                                 costs the step's inequality taken from the tank at its end;
                                 where the tank holds less than that unit (tank_cap 0, an
                                 empty tank, the guard off) the sum is rounded up, at most a
                                 unit above it. A fallback state reports work_anchor as the
                                 moved anchors' V change rounded up */
    edmi_real diss_damping; /*!< energy the dampers removed (>= 0) */
    edmi_real diss_scheme;  /*!< energy the scheme removed: sum over links of (work of the
                                 algorithmic force) - (V(d_n+1) - V(d_n)); >= 0 for GE/PM/PT,
                                 ~0 for LG, either sign for MP. With energy_balance in
                                 double-word arithmetic; with the guard alone as its
                                 certificate evaluated it (res.certificate) */
    edmi_real dh;           /*!< H_n+1 - H_n of the stored states as evaluated (double-word
                                 with energy_balance; with the guard alone as its
                                 certificate evaluated it), rounded */
    edmi_real diss_guard;   /*!< energy the guard's changes removed: H change of Newton's
                                 iterate minus that of the stored state (0 when the tank
                                 covered the step, as on most steps) */
    unsigned guard_action;  /*!< EDMI_MOVE_IMPULSE | _DRAG | _ROUND | _STOP | _HOLD: what the
                                 guard did */
    edmi_certificate certificate; /*!< how the guard (or energy_balance) evaluated the step */
    edmi_real tank;         /*!< the energy tank after the step, T_n+1 (sys->tank) */
    edmi_real tank_cap;     /*!< its capacity at the step's end: params.tank_cap EDMI_EPS
                                 times the magnitude of H's terms there [energy] */
    int substeps;           /*!< substeps stored: 1 for the step itself, more where it failed
                                 and params.substep_levels split it (the works, dissipations,
                                 dh and iterations above are their sums) */
    int fallbacks;          /*!< substeps (or the step) that stored the fallback state */
    edmi_status cause;      /*!< EDMI_OK if the step solved at once; else why it did not (the
                                 failure the substeps or the fallback then took over) */
} edmi_step_result;

/** Invariants of a state (section 2 and 4.1 of the paper). */
typedef struct edmi_invariants {
    edmi_real h;    /*!< Hamiltonian H = K + V */
    edmi_real k;    /*!< kinetic energy K */
    edmi_real v;    /*!< potential energy V (sum over links, plus -sum m g.q with a field) */
    edmi_real j[3]; /*!< angular momentum J = sum q x p (about the origin) */
    edmi_real l[3]; /*!< linear momentum L = sum p */
    edmi_real c[3]; /*!< centre-of-mass invariant C(t) = (sum m q - t L) / sum m */
} edmi_invariants;

/* ------------------------------------------------------------------------------------------
 * Build a system
 * ---------------------------------------------------------------------------------------- */

/** \brief Defaults: scheme PM (energy-safe: with the guard, H never rises), LG closed form,
 *  alternate Janz, tol_q 1e-8 (double; 1e-3 in float), tol_r = tol_a = 0 (Newton runs to its
 *  round-off floor), l_max 20, guard AUTO, no fallback, no energy_balance. */
edmi_params edmi_default_params(void);

/** \brief Empty the system and set its parameters.
 *  \param[out] sys the system
 *  \param[in] params parameters, or NULL for edmi_default_params()
 *  \return EDMI_OK, EDMI_ERR_NULL (sys), EDMI_ERR_PARAM (params invalid; sys untouched) */
edmi_status edmi_init(edmi_system *sys, const edmi_params *params);

/** \brief Replace the parameters (e.g. switch scheme between steps).
 *  \return EDMI_OK, EDMI_ERR_NULL, EDMI_ERR_PARAM, EDMI_ERR_CORRUPT */
edmi_status edmi_set_params(edmi_system *sys, const edmi_params *params);

/** \brief Append a body.
 *  \param[in] m mass > 0; \param[in] q position; \param[in] p momentum
 *  \param[out] index the new body's index, or NULL
 *  \return EDMI_OK, EDMI_ERR_NULL (sys, q or p), EDMI_ERR_UNINIT (sys not set up by
 *          edmi_init()), EDMI_ERR_MASS, EDMI_ERR_NONFINITE, EDMI_ERR_CAPACITY, EDMI_ERR_CORRUPT */
edmi_status edmi_add_body(edmi_system *sys, edmi_real m, const edmi_real q[3],
                          const edmi_real p[3], int *index);

/** \brief Link bodies a != b with a pair potential.
 *  \return EDMI_OK, EDMI_ERR_NULL, EDMI_ERR_UNINIT, EDMI_ERR_INDEX, EDMI_ERR_PARAM,
 *          EDMI_ERR_NONFINITE, EDMI_ERR_COINCIDENT (the two bodies at one point and a
 *          potential not defined at distance 0: every one but harmonic of rest length 0),
 *          EDMI_ERR_CAPACITY, EDMI_ERR_CORRUPT */
edmi_status edmi_add_pair(edmi_system *sys, int a, int b, const edmi_potential *pot,
                          int *index);

/** \brief Tie body a to the fixed point x with a potential of the distance ||q_a - x||.
 *  \return EDMI_OK, EDMI_ERR_NULL, EDMI_ERR_UNINIT, EDMI_ERR_INDEX, EDMI_ERR_PARAM,
 *          EDMI_ERR_NONFINITE, EDMI_ERR_COINCIDENT (x at the body and a potential not
 *          defined at distance 0), EDMI_ERR_CAPACITY, EDMI_ERR_CORRUPT */
edmi_status edmi_add_anchor(edmi_system *sys, int a, const edmi_real x[3],
                            const edmi_potential *pot, int *index);

/** \brief Set a uniform field: every body feels the constant force m g (adds V = -sum m g.q).
 *  \return EDMI_OK, EDMI_ERR_NULL, EDMI_ERR_NONFINITE, EDMI_ERR_CORRUPT */
edmi_status edmi_set_field(edmi_system *sys, const edmi_real g[3]);

/** \brief Put a linear viscous damper on a link: it pushes the link's ends apart or together
 *  with c times their relative speed along the link (dissipative, conserves L, J and C).
 *  \return EDMI_OK, EDMI_ERR_NULL, EDMI_ERR_UNINIT, EDMI_ERR_INDEX (no such link),
 *          EDMI_ERR_PARAM (c < 0 or not finite), EDMI_ERR_DISABLED (EDMI_MAX_DAMPERS is 0),
 *          EDMI_ERR_CAPACITY, EDMI_ERR_CORRUPT */
edmi_status edmi_add_damper(edmi_system *sys, int link, edmi_real c, int *index);

/** \brief Put body a against the plane n.x = c (n need not be unit: it is stored normalised)
 *  with the potential pot of the gap g = n.q_a - c (edmi_wall). *index (if not NULL) receives
 *  the wall's number, for sys->wall_force.
 *  \return EDMI_OK, EDMI_ERR_NULL, EDMI_ERR_UNINIT, EDMI_ERR_INDEX (no such body),
 *          EDMI_ERR_NONFINITE (n or c), EDMI_ERR_PARAM (n of length 0, or a potential a wall
 *          does not take: edmi_wall), EDMI_ERR_DISABLED (its kind compiled out, or
 *          EDMI_MAX_WALLS is 0), EDMI_ERR_CAPACITY, EDMI_ERR_CORRUPT */
edmi_status edmi_add_wall(edmi_system *sys, int a, const edmi_real n[3], edmi_real c,
                          const edmi_potential *pot, int *index);

/** \brief Move wall w along its normal: its offset goes from c to c_next over the next step,
 *  linearly in time (as edmi_move_anchor() moves an anchor). The work this motion does on the
 *  system, -Lambda (c_next - c) with Lambda the wall's discrete force V'(g), is added to
 *  edmi_step_result.work_anchor; after the step the wall rests at c_next until moved again.
 *  \return EDMI_OK, EDMI_ERR_NULL, EDMI_ERR_INDEX (no such wall), EDMI_ERR_NONFINITE,
 *          EDMI_ERR_DISABLED (EDMI_MAX_WALLS is 0), EDMI_ERR_CORRUPT */
edmi_status edmi_move_wall(edmi_system *sys, int w, edmi_real c_next);

/** \brief Couple the masses of bodies a and b: set the off-diagonal entry m_ab = m_ba of the
 *  mass matrix M (kinetic energy K = 1/2 p . M^-1 p; the diagonal entries are the bodies'
 *  masses), e.g. m/6 per bar element of mass m with a consistent mass matrix (whose ends then
 *  have body mass m/3 each from that element). m_ab = 0 uncouples them. Needs
 *  EDMI_MAX_MASS_GAP >= |a - b|. Every scheme steps M (q_n+1 - q_n) = dt p_n+1/2, the field
 *  pulls body a with (M 1)_a g, and the passivity guard certifies its inequality with
 *  K = 1/2 p . M^-1 p, its error bounded through a certified lower bound on M's smallest
 *  eigenvalue (a shifted Cholesky factorisation, Rump): any symmetric positive definite M
 *  whose smallest eigenvalue that bound proves positive is accepted (consistent triangles
 *  and tetrahedra included), any other refused here with EDMI_ERR_MASS.
 *  \return EDMI_OK, EDMI_ERR_NULL, EDMI_ERR_INDEX (a or b no body, or a == b),
 *          EDMI_ERR_NONFINITE, EDMI_ERR_CAPACITY (|a - b| > EDMI_MAX_MASS_GAP, or the Newton
 *          matrix would outgrow EDMI_MAX_MATRIX), EDMI_ERR_MASS (M would not be positive
 *          definite, or not provably so in working precision); on any error sys is unchanged */
edmi_status edmi_set_mass_coupling(edmi_system *sys, int a, int b, edmi_real m_ab);

/** \brief Set the energy tank T (edmi_system.tank): 0 empties it; a value read from sys.tank
 *  restores it with a saved state. The guard lets a later step spend what the tank holds
 *  (at most its capacity after that step).
 *  \return EDMI_OK, EDMI_ERR_NULL, EDMI_ERR_NONFINITE, EDMI_ERR_PARAM (t < 0, or t > 0 with
 *          params.tank_cap 0: the per-step form keeps no tank), EDMI_ERR_CORRUPT; on any
 *          error sys is unchanged */
edmi_status edmi_set_tank(edmi_system *sys, edmi_real t);

/** \brief Move the anchor of link `link` during the next step: it goes from its current
 *  position to x (straight, at constant speed) while the step runs, and stays at x after it.
 *  The work this motion does on the system is reported in edmi_step_result.work_anchor and
 *  the guard's inequality includes it. Call again before every step the anchor moves in.
 *  \return EDMI_OK, EDMI_ERR_NULL, EDMI_ERR_INDEX (no such link, or not an anchor link),
 *          EDMI_ERR_NONFINITE, EDMI_ERR_CORRUPT */
edmi_status edmi_move_anchor(edmi_system *sys, int link, const edmi_real x[3]);

/** \brief Set body a's external force port; the force is held constant over each step until
 *  set again (its work F . (q_n+1 - q_n) is reported in edmi_step_result.work_ext).
 *  \return EDMI_OK, EDMI_ERR_NULL, EDMI_ERR_INDEX, EDMI_ERR_NONFINITE, EDMI_ERR_CORRUPT */
edmi_status edmi_set_force(edmi_system *sys, int a, const edmi_real f[3]);

/** \brief Replace the system by a scene (t = 0, no force ports). Everything is validated
 *  first: on any error the system is unchanged.
 *  \return EDMI_OK, EDMI_ERR_NULL, EDMI_ERR_PARAM (also a negative count), EDMI_ERR_CAPACITY,
 *          EDMI_ERR_MASS, EDMI_ERR_NONFINITE, EDMI_ERR_INDEX, EDMI_ERR_COINCIDENT (a link's
 *          ends meet with a potential undefined there), EDMI_ERR_DISABLED */
edmi_status edmi_load_scene(edmi_system *sys, const edmi_scene *scene);

/** \brief Potential constructors (no validation here; edmi_add_pair/anchor validate). */
edmi_potential edmi_pot_harmonic(edmi_real k, edmi_real r0);
edmi_potential edmi_pot_quartic(edmi_real k, edmi_real len);
edmi_potential edmi_pot_neo_hooke(edmi_real c, edmi_real rbar);
edmi_potential edmi_pot_lj(edmi_real eps, edmi_real sigma);
edmi_potential edmi_pot_inverse(edmi_real k);
edmi_potential edmi_pot_user(edmi_user_pot_fn fn, edmi_user_dd_fn dd, void *ctx);
edmi_potential edmi_pot_contact(edmi_real k, edmi_real radius);
edmi_potential edmi_pot_tether(edmi_real k, edmi_real len);

/* ------------------------------------------------------------------------------------------
 * Step it
 * ---------------------------------------------------------------------------------------- */

/** \brief Advance the system by dt with its scheme (Newton predictor multi-corrector).
 *  The system changes only when EDMI_OK is returned.
 *  \param[in,out] sys the system; \param[in,out] work its workspace; \param[in] dt > 0
 *  \param[out] res what the step did, or NULL
 *  With the guard on (params.guard), the stored state and the tank T (sys->tank) satisfy
 *  H(q_n+1, p_n+1) - H(q_n, p_n) <= res->work_ext + res->work_anchor + T_n - T_n+1 exactly,
 *  with 0 <= T_n+1 <= res->tank_cap (T_n+1 = T_n = 0 when params.tank_cap is 0).
 *  Which outcome to read, and when: the status says whether the step was stored (EDMI_OK)
 *  or not (any other: the system is as it was; res is zeroed where the input was refused,
 *  and holds the failed attempt's counts otherwise). After EDMI_OK, res->stop says how:
 *  every stop but EDMI_STOP_FALLBACK means solved, to the bound EDMI_SOLVED states;
 *  EDMI_STOP_FALLBACK means the passive fallback state was stored instead
 *  (params.fallback). res->cause says why a stored step
 *  was not solved at once (EDMI_OK where it was): the failure that made it take substeps or
 *  the fallback, res->substeps and res->fallbacks how many of each it stored. A firmware
 *  reads the status every tick and counts res->stop == EDMI_STOP_FALLBACK; res->cause is for
 *  diagnosis. A step that fails once its input is accepted (SINGULAR,
 *  NO_CONVERGENCE, DIVERGED, PASSIVITY, OVERFLOW, END_STATE) is split into substeps with
 *  params.substep_levels, and with params.fallback stores the fallback state where that still
 *  fails (res->cause says why, res->substeps and res->fallbacks what was stored).
 *  \return EDMI_OK, EDMI_ERR_NULL, EDMI_ERR_DT, EDMI_ERR_MASS, EDMI_ERR_NONFINITE,
 *          EDMI_ERR_CORRUPT, EDMI_ERR_CAPACITY (the Newton matrix store outgrown),
 *          EDMI_ERR_INDEX, EDMI_ERR_PARAM,
 *          EDMI_ERR_COINCIDENT, EDMI_ERR_RANGE, EDMI_ERR_DOMAIN (the start state's
 *          potentials undefined or beyond the range): the input refused; without
 *          params.fallback also the step's failures EDMI_ERR_SINGULAR,
 *          EDMI_ERR_NO_CONVERGENCE, EDMI_ERR_DIVERGED, EDMI_ERR_PASSIVITY, EDMI_ERR_OVERFLOW,
 *          EDMI_ERR_END_STATE; with it, only where a moved anchor or wall leaves no passive
 *          state: EDMI_ERR_END_STATE (a moved anchor ends on its body or outside its
 *          potential's domain), EDMI_ERR_OVERFLOW (a moved anchor's or wall's energy at the
 *          kept positions beyond the range), or, with substeps, EDMI_ERR_COINCIDENT,
 *          EDMI_ERR_RANGE, EDMI_ERR_DOMAIN at a substep's start the moving anchor refuses.
 *          EDMI_ERR_DT also when t + dt overflows. */
edmi_status edmi_step(edmi_system *sys, edmi_workspace *work, edmi_real dt,
                      edmi_step_result *res);

/* ------------------------------------------------------------------------------------------
 * Measure it
 * ---------------------------------------------------------------------------------------- */

/** \brief H, K, V, J, L and C(t) of the current state. Checks the system as edmi_step
 *  does (a caller may have written its fields); *out is written only on success.
 *  \return EDMI_OK, EDMI_ERR_NULL, EDMI_ERR_CORRUPT, EDMI_ERR_CAPACITY, EDMI_ERR_PARAM,
 *          EDMI_ERR_MASS, EDMI_ERR_NONFINITE, EDMI_ERR_INDEX, EDMI_ERR_COINCIDENT (a
 *          potential undefined at d = 0), EDMI_ERR_DOMAIN (a user potential refused a
 *          distance), EDMI_ERR_OVERFLOW (an invariant beyond the range) */
edmi_status edmi_invariants_of(const edmi_system *sys, edmi_invariants *out);

/** \brief Derivatives 0..4 of the split parts of a potential at r > 0.
 *  \return EDMI_OK, EDMI_ERR_NULL, EDMI_ERR_PARAM (invalid potential or r <= 0),
 *          EDMI_ERR_DOMAIN (user callback refused r), EDMI_ERR_OVERFLOW (a derivative is not
 *          finite at r: beyond the range); *out is written only on success */
edmi_status edmi_pot_eval(const edmi_potential *pot, edmi_real r, edmi_pot_parts *out);

/** \brief Closed-form divided difference [V(d1)-V(d0)]/(d1-d0) and its d1-derivative,
 *  finite at d1 == d0 (then V'(d0) and V''(d0)/2).
 *  \return EDMI_OK, EDMI_ERR_NULL, EDMI_ERR_PARAM (invalid, d <= 0, or a user potential
 *          without dd), EDMI_ERR_DOMAIN (user callback refused), EDMI_ERR_OVERFLOW;
 *          the outputs are written only on success */
edmi_status edmi_pot_divdiff(const edmi_potential *pot, edmi_real d0, edmi_real d1,
                             edmi_real *dd, edmi_real *dd_d1);

/* ------------------------------------------------------------------------------------------
 * Verify it: the residual and consistent tangent Newton uses, for tests and diagnostics
 * ---------------------------------------------------------------------------------------- */

/** \brief Residuals R_q, R_p of the scheme at a trial end state (q1, p1) for a step dt from
 *  the system's current state (arrays of sys->n_bodies rows). Does not change sys.
 *  \param[out] lg_switches links on the LG alternate force (may be NULL)
 *  \return EDMI_OK, EDMI_ERR_NULL, EDMI_ERR_DT, the system's errors as edmi_step() checks
 *          them (EDMI_ERR_CORRUPT, EDMI_ERR_CAPACITY ... EDMI_ERR_PARAM), EDMI_ERR_COINCIDENT,
 *          EDMI_ERR_RANGE (the start state refused, as edmi_step() does), EDMI_ERR_DOMAIN
 *          (the start or the trial puts a link or its mid-point at length 0, or where a user
 *          callback refuses), EDMI_ERR_OVERFLOW (a residual beyond the range); rq, rp
 *          and *lg_switches are written only on success */
edmi_status edmi_residual(const edmi_system *sys, edmi_workspace *work, edmi_real dt,
                          const edmi_real (*q1)[3], const edmi_real (*p1)[3],
                          edmi_real (*rq)[3], edmi_real (*rp)[3], int *lg_switches);

/** \brief Consistent tangent dR_p/dq1 at the trial end state, dense row-major
 *  (3 n_bodies)^2 into kmat (dR_q/dq1 = I and dR_p/dp1 = I, dR_q/dp1 = -dt/(2m) I are exact).
 *  \return as edmi_residual(), and EDMI_ERR_OVERFLOW (a block beyond the range); kmat is
 *          written only on success */
edmi_status edmi_tangent(const edmi_system *sys, edmi_workspace *work, edmi_real dt,
                         const edmi_real (*q1)[3], const edmi_real (*p1)[3], edmi_real *kmat);

/* ------------------------------------------------------------------------------------------
 * Misc
 * ---------------------------------------------------------------------------------------- */

/** \brief A constant English name of a status ("EDMI_OK", ...). */
const char *edmi_status_name(edmi_status s);

/** \brief 1 if this build uses double precision, 0 if float: check it against the
 *  header your code was compiled with, since the precision changes the ABI. */
int edmi_is_double_precision(void);

/** \brief 1 if the caller's edmi_system and edmi_workspace have the library's sizes, 0 if
 *  not: EDMI_REAL or an EDMI_MAX_* capacity (an EDMI_USER_CONFIG file) differs between the
 *  caller's translation unit and edmi.c, and every call would corrupt memory. Call it as
 *  EDMI_CONFIG_MATCHES() once at start-up, from each translation unit that owns a system. */
int edmi_config_matches(unsigned long system_size, unsigned long workspace_size);

/** edmi_config_matches() with this translation unit's sizes. */
#define EDMI_CONFIG_MATCHES() \
    edmi_config_matches((unsigned long)sizeof(edmi_system), (unsigned long)sizeof(edmi_workspace))

/* ==========================================================================================
 * Layouts for sizing only. A caller allocates an edmi_workspace (static, or on a stack that
 * can hold sizeof(edmi_workspace)) and passes it to edmi_step(); nothing here is API: read or
 * write none of these fields. Their sizes are in docs/sizing.md.
 * ======================================================================================== */

/* Per-link scratch: the start-of-step quantities a link's force needs, computed once per
 * step, and the link's tangent block. */
typedef struct edmi_link_ws {
    edmi_real r0[3]; /* link vector r_n = q_A,n - q_B,n (or - anchor) */
    edmi_real d0;    /* d_n = |r_n| */
    edmi_real v0;    /* V(d_n) */
    edmi_real dv0;   /* V'(d_n) */
    edmi_real dve0;  /* V_e'(d_n) */
    edmi_real d3p0;  /* V_+'''(d_n) */
    edmi_real d3m0;  /* V_-'''(d_n) */
    edmi_real m0;    /* the magnitude of V's terms at d_n (the guard's plain error bound) */
    edmi_real d1, v1, m1; /* d_n+1, V(d_n+1) and its magnitude at the last evaluation, when
                             the scheme evaluated V there (have1) */
    edmi_real beta;    /* beta of the last residual evaluation (energy balance, guard) */
    edmi_real noise;   /* LG quotient: its cancellation error in the link's force */
    edmi_real x1[3];   /* anchor links: the anchor at the end of the step */
    edmi_real f[3];    /* mean force on the second end over the step (sys->link_force) */
    edmi_real gamma;   /* the tangent block d f / d r_{n+1} = dt (beta/2 I + gamma r_m u^T) */
    edmi_real rm[3];   /* of the last evaluation, built only where a correction needs it */
    edmi_real u[3];
    /* the link's terms of the step's energy balance: V change and scheme work (value and
     * error of each as a double-word pair), error bound, size; bal_on: any end moved */
    edmi_real bal_dv[2], bal_sc[2], bal_err, bal_size;
    /* at the end of the last balance: the link's two ends, the potential's parameters,
     * |r|^2 and V (double-word) and V's error bound, reused when the next step starts there */
    edmi_real end_ends[6], end_pot[2], end_s[2], end_v[2], end_e;
    /* substeps (edmi_params.substep_levels): the mean force summed over them, and a moving
     * anchor's start and end over the whole step */
    edmi_real fsum[3], xs[3], xt[3];
    int bal_on;
    int have1;
    int end_kind;
} edmi_link_ws;

/* Newton's scratch space (typedef above). */
struct edmi_workspace {
    edmi_real q1[EDMI_MAX_BODIES][3]; /* iterate q_{n+1,(l)} */
    edmi_real p1[EDMI_MAX_BODIES][3]; /* iterate p_{n+1,(l)} */
    edmi_real rq[EDMI_MAX_BODIES][3]; /* residual R_q */
    edmi_real rp[EDMI_MAX_BODIES][3]; /* residual R_p */
    edmi_real sq[EDMI_MAX_BODIES];    /* per-body position scale of the stopping test */
    edmi_real sp[EDMI_MAX_BODIES];    /* per-body momentum scale of the stopping test */
    edmi_real dp[EDMI_MAX_BODIES][3]; /* Newton correction of p */
    edmi_real h[EDMI_MAX_BODIES];     /* dt / (2 m) per body, the Newton matrix's row scales */
    edmi_real rhs[3 * EDMI_MAX_BODIES]; /* right-hand side, then the correction of q */
    edmi_real q0[EDMI_MAX_BODIES][3]; /* substeps: the step's start, restored if they fail */
    edmi_real p0[EDMI_MAX_BODIES][3];
    edmi_real mat[EDMI_MAX_MATRIX];    /* Newton matrix: element (i, j) at mat[row[i] + j] */
    edmi_link_ws lw[EDMI_MAX_LINKS];
#if EDMI_MAX_WALLS > 0
    edmi_link_ws ww[EDMI_MAX_WALLS]; /* walls: d0 = g_n, beta = Lambda, gamma = d Lambda / d g */
#endif
    edmi_real kd[EDMI_DAMPER_SLOTS_][9]; /* damper tangent blocks */
    edmi_real kend[EDMI_MAX_BODIES][5];  /* p and |p|^2 (double-word) at the last balance's end */
    int row[3 * EDMI_MAX_BODIES];      /* the Newton matrix's row offsets */
    int order[EDMI_MAX_LINKS];         /* link indices: the n_pair pair links, then anchors */
    int n_pair;
    int piv[3 * EDMI_MAX_BODIES];      /* the factored Newton matrix's pivot rows */
    int kb, upper;                     /* its lower and upper bandwidths */
    /* The factors kept for a system's next step (edmi_step): whose they are (set by the
     * step that stored them, cleared by any call that writes the matrix), whether this call
     * found them kept, and whether it factored. */
    const void *kept_sys;
    int kept, fresh;
};

#ifdef __cplusplus
}
#endif
#endif /* EDMI_H */
