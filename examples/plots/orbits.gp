# Planet orbits projected on the x-y plane of the ICRF, sampled every 50 days (the paper's
# Figs. inner_planets_orbits, outer_planets_orbits), one panel per scheme; a dot marks the
# initial position.
# Variables: data, out, bodies (e.g. "1 2 3 4"), names, range, name
load 'examples/plots/common.gp'
set terminal png size 1000,700 font "sans,9"
set output out
f(s) = data . '/solar_' . s . '.csv'
PCOL(i) = word("#555555 #e08a00 #1f4fd1 #d12f1f #9b30c8", i)
B(i) = int(word(bodies, i))
set size ratio -1
set xrange [-range:range]
set yrange [-range:range]
set xlabel 'x [AU]'
set ylabel 'y [AU]'
unset key
set multiplot layout 2,3 title name
do for [s in S] {
    set title TITLE(s) . ', dt = 5 days'
    plot for [i = 1:words(bodies)] f(s) using (qx(B(i))):(qy(B(i))) with points pt 7 ps 0.08 lc rgb PCOL(i), \
         for [i = 1:words(bodies)] f(s) using (qx(B(i))):(qy(B(i))) every ::0::0 \
             with points pt 7 ps 0.7 lc rgb 'black'
}
# the sixth panel: the legend
unset title
unset border
unset tics
unset xlabel
unset ylabel
set key center center box font ",10" spacing 1.5 samplen 1
plot for [i = 1:words(bodies)] NaN with points pt 7 ps 1.2 lc rgb PCOL(i) title word(names, i), \
     NaN with points pt 7 ps 0.7 lc rgb 'black' title 'position at t = 0'
unset multiplot
