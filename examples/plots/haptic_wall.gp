# examples/haptic_wall.c's passivity map: a 0.1 kg device with damping b bouncing on a wall at
# 1 kHz. Left: the wall rendered explicitly (F = K x each tick); right: an edmi wall behind the
# README's virtual coupling (Kc = 3 N/mm, c = 0.5 N s/m). A point is the energy ratio
# e^2 = KE out / KE in of the bounce: filled red where the loop created energy (e^2 > 1), open
# black where it did not (a device that came to rest in the wall counts as passive).
# Variables: data (holds haptic_wall.csv), out. CSV: kind, stiffness, b, e2 (e2 -1: at rest).
load 'examples/plots/common.gp'
set terminal png size 1000,420 font "sans,9"
set output out
f = data . '/haptic_wall.csv'
set multiplot layout 1,2 title "A device of 0.1 kg touching a wall in a 1 kHz loop (examples/haptic\\_wall.c): red, the loop created energy"
set logscale x
set xlabel 'wall stiffness K [N/m]'
set ylabel 'device damping b [N s/m]'
set yrange [-0.5:21]
set key top left font ",8"
set title 'explicit wall, F = K x sampled each tick'
plot f using ($1 == 0 && $4 > 1 ? $2 : 1/0):3 with points pt 7 ps 1.2 lc rgb '#d12f1f' title 'active', \
     f using ($1 == 0 && $4 <= 1 ? $2 : 1/0):3 with points pt 6 ps 1.2 lc rgb '#000000' title 'passive', \
     [200:50000] x * 1e-3 / 2 with lines lw 1.5 lc rgb '#1f4fd1' title 'b = K T / 2'
set xlabel 'edmi wall stiffness k [N/m^2] (contact k/3 x^3)'
set title 'edmi wall behind a virtual coupling (Kc = 3000 N/m, c = 0.5 N s/m)'
plot f using ($1 == 1 && $4 > 1 ? $2 : 1/0):3 with points pt 7 ps 1.2 lc rgb '#d12f1f' title 'active', \
     f using ($1 == 1 && $4 <= 1 ? $2 : 1/0):3 with points pt 6 ps 1.2 lc rgb '#000000' title 'passive', \
     [5e5:2e12] 2.0 with lines lw 1.5 lc rgb '#1f4fd1' title 'b = Kc T / 2 + c'
unset multiplot
