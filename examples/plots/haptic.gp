# The 1 kHz virtual coupling of examples/haptic.c: the hand, and the energy each integrator
# injects, E_inj(t) = H(t) - H_0 - (work the hand did), which a passive simulation keeps <= 0.
# Variables: data (holds haptic.csv), out, prec (EDMI_REAL of the run). The png terminal
# draws no dashes: curves differ by colour.
# CSV columns: 1 t, 2 x_hand, then per method m = 0..5 (edmi, fe, se, vv, edmi_extrap,
# edmi_late): 3+4m q, 4+4m F on the hand, 5+4m E_inj, 6+4m H_n+1 - H_n - W_n of the tick.
load 'examples/plots/common.gp'
set terminal png size 1000,680 font "sans,9"
set output out
f = data . '/haptic.csv'
Q(m) = column(3 + 4 * m)
E(m) = column(5 + 4 * m)
X(m) = column(6 + 4 * m)
MAIN = "0 3 2 1"
NAME(m) = m == 0 ? "edmi PM" : m == 1 ? "explicit Euler" : m == 2 ? "semi-implicit Euler" : \
          "velocity Verlet"
MCOL(m) = word("#000000 #d12f1f #1f4fd1 #2a9d3a", m + 1)
MLW(m) = m == 0 ? 2.0 : 1.2
# the flicks of examples/haptic_hand.h
FLICKS = "0.8 1.9 2.9 3.6 4.7"
set multiplot layout 2,2 title "1 kHz virtual coupling (examples/haptic.c, EDMI\\_REAL = " . \
    prec . "): tool 0.1 kg, spring 3 N/mm, damper 0.5 N s/m, five fast flicks of the hand"

set title 'hand and tool (edmi PM)'
set xlabel 'time [s]'
set ylabel 'position [mm]'
set xrange [0:6]
set key top right font ",8"
do for [i = 1:words(FLICKS)] {
    set arrow i from first word(FLICKS, i) + 0, graph 0 to first word(FLICKS, i) + 0, graph 1 \
        nohead lc rgb '#cccccc' dt 3
}
plot f using 1:($2 * 1e3) with lines lw 2.5 lc rgb '#e08a00' title 'hand x(t)', \
     f using 1:(Q(0) * 1e3) with lines lw 0.8 lc rgb 'black' title 'tool q(t)'
unset arrow

set title 'E_{inj}(t): energy created beyond the hand''s work'
set ylabel 'E_{inj} [mJ]'
set yrange [-560:60]
set key bottom left font ",8"
set label 1 "explicit Euler diverges (B < K dt)" at 0.45, 30 \
    tc rgb '#d12f1f' font ",8"
plot 0 with lines lc rgb '#888888' dt 2 notitle, \
     for [m in MAIN] f using 1:(E(m) * 1e3) with lines lw MLW(m) lc rgb MCOL(m) \
        title NAME(m + 0), \
     f using 1:(E(4) * 1e3) with lines lw 1.2 lc rgb '#9b30c8' title 'edmi PM, causal loop'
unset label 1
set key default

set title 'the first flick (t = 0.8 s): semi-implicit Euler and the causal loops go above 0'
set xrange [0.79:0.92]
set yrange [-25:6]
set xtics 0.02
set key bottom left font ",8"
plot 0 with lines lc rgb '#888888' dt 2 notitle, \
     for [m in "0 3 2"] f using 1:(E(m) * 1e3) with lines lw MLW(m) lc rgb MCOL(m) \
        title NAME(m + 0), \
     f using 1:(E(4) * 1e3) with lines lw 1.2 lc rgb '#9b30c8' \
        title 'edmi PM, causal: hand extrapolated', \
     f using 1:(E(5) * 1e3) with lines lw 1.2 lc rgb '#999999' \
        title 'edmi PM, causal: force one tick late'
set xtics autofreq
set key default

set title 'ticks on which H rose by more than the hand''s work (edmi PM: none)'
set xrange [0:6]
set logscale y
set yrange [1e-12:1]
set format y '10^{%L}'
set ylabel 'H_{n+1} - H_n - W_n > 0 [J]'
set key bottom right font ",8"
plot for [m in "1 2 3"] f using 1:(X(m) > 0 ? X(m) : NaN) with points pt 7 ps 0.25 \
        lc rgb MCOL(m) title NAME(m + 0), \
     f using 1:(X(0) > 0 ? X(0) : NaN) with points pt 7 ps 0.6 lc rgb 'black' title NAME(0)
unset multiplot
