# Momentum and centre-of-mass errors of every scheme (the paper's Figs. two_particle_momentum,
# solar_momentum), as norms on a log scale.
# Variables: data, out, xt (x tic step), prefix (CSV files DATA/PREFIXscheme.csv), name, tscale, tunit
load 'examples/plots/common.gp'
set terminal png size 1050,360 font "sans,9"
set output out
f(s) = data . '/' . prefix . s . '.csv'
set logscale y
set format y '10^{%L}'
set xlabel 'time [' . tunit . ']'
set xtics xt
set key bottom right font ",8"
set multiplot layout 1,3 title name
set title 'angular momentum |J - J_0|'
plot for [s in S] f(s) using ($1/tscale):($13 > 0 ? $13 : NaN) with lines lw 1 lc rgb COLOR(s) title SHORT(s)
set title 'linear momentum |L - L_0|'
plot for [s in S] f(s) using ($1/tscale):($14 > 0 ? $14 : NaN) with lines lw 1 lc rgb COLOR(s) title SHORT(s)
set title 'centre of mass |C(t) - C_0|'
plot for [s in S] f(s) using ($1/tscale):($15 > 0 ? $15 : NaN) with lines lw 1 lc rgb COLOR(s) title SHORT(s)
unset multiplot
