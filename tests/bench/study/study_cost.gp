# Position error at T against instructions to T, one panel per scene (make study).
load 'tests/bench/study/study_common.gp'
set multiplot layout 2,3 title "Position error at T (max over bodies, against the converged reference) vs instructions to T (callgrind, x86-64 -O2)"
set xlabel 'instructions to T'
set ylabel 'position error at T'
unset key
do for [s in scenes] {
    set title s
    plot for [m in methods] dat(s, m, 'double') u 1:2 w lp lw 1.5 pt 7 ps 0.6 \
             dt edmi(m) ? 1 : 2 lc rgb colour(m) title m, \
         dat(s, 'pm', 'float') u 1:2 w lp lw 1.5 pt 6 ps 0.8 dt 3 lc rgb '#000000' title 'pm (float)', \
         dat(s, 'pm', 'double_tol') u 1:2 w p pt 4 ps 1.2 lc rgb '#000000' title 'pm, tol_R 1e-2..1e-8'
}
# the legend in a panel of its own
set key center center box opaque font ',10' spacing 1.2
set title ''
unset border
unset tics
unset xlabel
unset ylabel
unset grid
set xrange [1:2]
set yrange [1:2]
unset logscale
plot for [m in methods] NaN w lp lw 1.5 pt 7 ps 0.6 dt edmi(m) ? 1 : 2 lc rgb colour(m) title m, \
     NaN w lp lw 1.5 pt 6 ps 0.8 dt 3 lc rgb '#000000' title 'pm (float)', \
     NaN w p pt 4 ps 1.2 lc rgb '#000000' title 'pm, tol_R 1e-2..1e-8 (middle dt)'
unset multiplot
