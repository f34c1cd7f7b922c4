# LG as the quotient with its alternate forces, the paper's tol_Q study
# (Figs. two_particle_hybird_labudde_greenspan, solar_hybird_labudde_greenspan): H - H0 for
# the Janz (default), GE and PM alternates (rows) at tol_Q = 1e-4, 1e-6, 1e-8 (columns).
# Variables: data, out, xt (x tic step), prefix (CSV files DATA/PREFIXq{4,6,8}_{janz,ge,pm}.csv), name, tscale, tunit
load 'examples/plots/common.gp'
set terminal png size 1050,720 font "sans,9"
set output out
f(q, a) = data . '/' . prefix . 'q' . q . '_' . a . '.csv'
ALT(a) = a eq "janz" ? "Janz (default)" : a eq "ge" ? "GE alternate" : "PM alternate"
ACOL(a) = a eq "janz" ? "#1f4fd1" : a eq "ge" ? "#d12f1f" : "#000000"
set format y '%.1e'
set xlabel 'time [' . tunit . ']'
set xtics xt
set ylabel '(H - H_0) / |H_0|'
unset key
set multiplot layout 3,3 title name
do for [a in "janz ge pm"] {
    do for [q in "4 6 8"] {
        set title 'LG-Q, ' . ALT(a) . ', tol_Q = 10^{-' . q . '}'
        plot f(q, a) using ($1/tscale):3 with lines lw 1.2 lc rgb ACOL(a) notitle
    }
}
unset multiplot
