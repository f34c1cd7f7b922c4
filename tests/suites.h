/* The test suites; each lives in its own file and is run by test_main.c. */
#ifndef EDMI_TEST_SUITES_H
#define EDMI_TEST_SUITES_H

void suite_potentials(void); /* test_potentials.c: derivatives, splits, divided differences */
void suite_contact(void);    /* test_contact.c: one-sided potentials, collisions, tethers */
void suite_invalid(void);    /* test_invalid.c: every bad input, system unchanged (memcmp) */
void suite_fuzz_findings(void); /* test_fuzz_findings.c: the API fuzzer's findings, fixed */
void suite_tangent(void);    /* test_tangent.c: consistent tangent vs finite differences, Newton */
void suite_energy(void);     /* test_energy.c: per-step energy laws, J/L/C conservation */
void suite_orders(void);     /* test_orders.c: observed convergence orders */
void suite_paper(void);      /* test_paper.c: the paper's H0, J0 and accuracy table */
void suite_hard(void);       /* test_hard.c: circular orbit, LG switch, near-collision, stiff */
void suite_solver(void);     /* test_solver.c: banded solve vs body numbering, bit-reproducible */
void suite_effects(void);    /* test_effects.c: field, dampers, ports, energy balance, scenes */
void suite_guard(void);      /* test_guard.c: passivity on stored states, d = 0, moving anchors */
void suite_track(void);      /* test_track.c: float tracks the double reference; schemes differ */
void suite_orbits(void);     /* test_orbits.c: the guard does not steer circular orbits */

#endif
