# H - H0 per scheme, one panel each (the paper's Figs. single_particle_energy, solar_energy),
# and a sixth panel with |J - J0| for every scheme.
# Variables: data, out, xt (x tic step), prefix (CSV files DATA/PREFIXscheme.csv), name, tscale, tunit
load 'examples/plots/common.gp'
set terminal png size 1000,560 font "sans,9"
set output out
f(s) = data . '/' . prefix . s . '.csv'
set format y '%.1e'
set xlabel 'time [' . tunit . ']'
set xtics xt
set multiplot layout 2,3 title name
unset key
do for [s in S] {
    set title TITLE(s)
    set ylabel '(H - H_0) / |H_0|'
    plot f(s) using ($1/tscale):3 with lines lw 1.2 lc rgb COLOR(s) notitle
}
set title 'angular momentum error |J - J_0|'
set logscale y
set format y '10^{%L}'
set ylabel '|J - J_0|'
set key bottom right font ",8"
plot for [s in S] f(s) using ($1/tscale):($13 > 0 ? $13 : NaN) with lines lw 1 lc rgb COLOR(s) title SHORT(s)
unset multiplot
