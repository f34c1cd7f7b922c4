# The hanging chain (every effect at once): the discrete energy balance and the bead paths.
# Variables: data, out
load 'examples/plots/common.gp'
set terminal png size 1000,400 font "sans,9"
set output out
f = data . '/chain_pm.csv'
stats f using 2 every ::0::0 nooutput
H0 = STATS_min
set multiplot layout 1,2 title "Hanging chain, PM, dt = 1e-3: field, six springs with dampers, a force port on the last bead"
set title 'energy balance, summed from t = 0'
set xlabel 'time [s]'
set ylabel 'energy [J]'
set xrange [0:5]
set yrange [-0.16:0.1]
set key top center horizontal maxrows 2 font ",8" samplen 2 width -2
plot f using 1:($2 - H0) with lines lw 3 lc rgb '#bbbbbb' title 'H - H_0', \
     f using 1:($17 - $18 - $19) with lines lw 1 dt 2 lc rgb 'black' title 'W_{ext} - D_{scheme} - D_{damping}', \
     f using 1:17 with lines lw 1.2 lc rgb '#1f4fd1' title 'W_{ext} (force port)', \
     f using 1:(-$19) with lines lw 1.2 lc rgb '#d12f1f' title '-D_{damping}', \
     f using 1:(-$18) with lines lw 1.2 lc rgb '#2a9d3a' title '-D_{scheme}'
set title 'bead paths (x-z plane), o = start, anchor at the origin'
set xlabel 'x [m]'
set ylabel 'z [m]'
set size ratio -1
set autoscale xy
set key off
plot for [b = 0:5] f using (qx(b)):(qz(b)) with lines lw 0.8 lc rgb word("#555555 #e08a00 #1f4fd1 #d12f1f #9b30c8 #2a9d3a", b + 1), \
     for [b = 0:5] f using (qx(b)):(qz(b)) every ::0::0 with points pt 6 ps 0.8 lc rgb 'black', \
     '+' using (0):(0) every ::0::0 with points pt 5 ps 1 lc rgb 'black'
unset multiplot
