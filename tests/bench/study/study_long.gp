# The spring's energy over 10^6 steps of 1e-3 (10^5 with STUDY_QUICK), double and float.
load 'tests/bench/study/study_common.gp'
set terminal pngcairo size 1500,560 font ',10' noenhanced
set output out
set multiplot layout 1,2 title "Paper spring, dt = 1e-3: max |H - H0|/|H0| over each block of 1000 steps (H in long double from the stored state)"
set xlabel 't'
set ylabel 'energy error'
set key bottom right
set yrange [1e-17:1]
lm = "verlet rk4 gsl-rk2imp mp lg pm"
f(m, p) = data . '/long_' . m . '_' . p . '.dat'
set title 'double'
plot for [m in lm] f(m, 'double') u 1:($2 > 0 ? $2 : 1e-17) w l lw 1.5 lc rgb colour(m) title m
set title 'float'
plot for [m in "verlet rk4 mp lg pm"] f(m, 'float') u 1:($2 > 0 ? $2 : 1e-17) w l lw 1.5 lc rgb colour(m) title m
unset multiplot
