# The highest axial mode of the cable's bar as an edmi-sim scene (make_plots.sh).
#   awk -v consistent=0|1 -v dt=DT -v steps=N -f examples/plots/cable_mode.awk
# The cable of examples/scenes/cable_*.scene (8 elements: mass me = 0.05, stiffness k = 500,
# length L = 0.1), laid straight along x with no field, so the motion is linear. Lumped and
# consistent masses share the fixed-free bar's mode shapes u_j = sin(j th), th = (2i - 1) pi /
# (2 N) (both K and M are tridiagonal Toeplitz with the free end's row halved); the highest,
# i = N, is given an amplitude of 1e-2 L. Its exact FE frequencies:
#   lumped      omega^2 = 2 k (1 - cos th) / me
#   consistent  omega^2 = 6 k (1 - cos th) / (me (2 + cos th))
# and make_plots.sh passes them on in the title line.
BEGIN {
    N = 8; me = 0.05; k = 500; L = 0.1
    pi = atan2(0, -1); th = (2 * N - 1) * pi / (2 * N); co = cos(th)
    w = consistent ? sqrt(6 * k * (1 - co) / (me * (2 + co))) : sqrt(2 * k * (1 - co) / me)
    printf "title highest axial mode, %s mass, FE omega %.12g\n",
           consistent ? "consistent" : "lumped", w
    for (j = 1; j <= N; j++) {
        m = (j == N ? 0.5 : 1) * (consistent ? 2 * me / 3 : me)
        printf "body b%d %.17g %.17g 0 0  0 0 0\n", j, m, L * (j + 1e-2 * sin(j * th))
    }
    printf "anchor b1 0 0 0 harmonic %g %g\nchain b1 b%d harmonic %g %g\n", k, L, N, k, L
    for (j = 1; consistent && j < N; j++)
        printf "mass b%d b%d %.17g\n", j, j + 1, me / 6
    printf "set scheme pm\nset dt %s\nset t_end %.17g\n", dt, dt * steps
}
