# The hanging cable of 8 bar elements, consistent against lumped mass (make_plots.sh):
# the tip's path, the distance between the two tips, and the highest axial mode's frequency.
# Variables: data, out
load 'examples/plots/common.gp'
set terminal png size 1500,430 font "sans,9"
set output out
f = data . '/cable_tips.csv'
off = 67                      # columns per trace: 19 + 6 x 8 bodies; the lumped one follows
tipx = 20 + 6 * 7
set multiplot layout 1,3 title "Hanging cable, 8 bar elements, PM, dt = 1e-3: consistent against lumped mass"
set title "the tip's path (x-z plane), released from the horizontal"
set xlabel 'x [m]'
set ylabel 'z [m]'
set size ratio -1
set key bottom left font ",8"
plot f using (column(tipx)):(column(tipx + 2)) with lines lw 1.2 lc rgb '#1f4fd1' title 'consistent', \
     f using (column(off + tipx)):(column(off + tipx + 2)) with lines lw 1.2 lc rgb '#d12f1f' title 'lumped', \
     '+' using (0):(0) every ::0::0 with points pt 5 ps 1 lc rgb 'black' title 'fixed point'
set size noratio
set title 'distance between the two tips'
set xlabel 'time [s]'
set ylabel '|q_{tip, consistent} - q_{tip, lumped}| [m]'
set key off
dist(x, y, z) = sqrt(x * x + y * y + z * z)
plot f using 1:(dist(column(tipx) - column(off + tipx), column(tipx + 1) - column(off + tipx + 1), \
                     column(tipx + 2) - column(off + tipx + 2))) with lines lw 1.2 lc rgb 'black'
m = data . '/cable_modes.dat'
set datafile separator whitespace
set datafile nocolumnheaders
set title "highest axial mode of the straight bar: PM's frequency per step size"
set xlabel 'dt [s]'
set ylabel 'omega [rad/s]'
set logscale x
set format x '10^{%T}'
set yrange [0:*]
set xrange [5e-5:5e-2]
set key bottom left font ",8"
plot m using 1:2 with lines lw 1 lc rgb '#1f4fd1' title 'exact FE, consistent', \
     m using 1:3 with lines lw 3 lc rgb '#a8b8f0' title '(2/dt) atan(omega dt/2), consistent', \
     m using 1:4 with points pt 6 ps 1.2 lc rgb '#1f4fd1' title 'PM run, consistent', \
     m using 1:5 with lines lw 1 lc rgb '#d12f1f' title 'exact FE, lumped', \
     m using 1:6 with lines lw 3 lc rgb '#f0b0a8' title '(2/dt) atan(omega dt/2), lumped', \
     m using 1:7 with points pt 4 ps 1.2 lc rgb '#d12f1f' title 'PM run, lumped'
unset multiplot
