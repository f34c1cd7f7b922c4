# The paper's Fig. single_particle_orbits: the stiff neo-Hookean spring at dt = 1e-2, T = 10.
# MP wide light blue, LG thin red, the scheme of the panel thin black (the paper's MP dashed
# and LG dash-dot lines do not survive the png terminal, which has no dash patterns).
load 'examples/plots/common.gp'
set terminal png size 1050,400 font "sans,9"
set output out
# The orbit is planar (central force): plot it in its plane, basis e1 = q0/|q0|,
# e2 = n x e1 with n = J0/|J0|, J0 = q0 x p0 = (30, -120, 60).
nq = sqrt(6.0); e1x = 2.0/nq; e1y = 1.0/nq; e1z = 1.0/nq
nj = sqrt(30.0**2 + 120.0**2 + 60.0**2); nx = 30.0/nj; ny = -120.0/nj; nz = 60.0/nj
e2x = ny*e1z - nz*e1y; e2y = nz*e1x - nx*e1z; e2z = nx*e1y - ny*e1x
U = '(qx(0)*e1x + qy(0)*e1y + qz(0)*e1z)'
V = '(qx(0)*e2x + qy(0)*e2y + qz(0)*e2z)'
f(s) = data . '/spring_dt1e-2_' . s . '.csv'
set size ratio -1
set xlabel 'q . e_1'
set ylabel 'q . e_2'
set xrange [-6.5:6.5]
set yrange [-6.5:6.5]
set key top right font ",8"
set multiplot layout 1,3 title "Stiff neo-Hookean spring, dt = 1e-2, t = 0..10: orbit in its plane (e_1 = q_0/|q_0|, e_2 = J_0/|J_0| x e_1)"
do for [s in "ge pm pt"] {
    set title '(' . (s eq "ge" ? "a" : s eq "pm" ? "b" : "c") . ') ' . TITLE(s)
    plot f('mp') using @U:@V with lines lw 4 lc rgb '#8fb0ff' title 'MP', \
         f('lg') using @U:@V with lines lw 1 lc rgb '#d12f1f' title 'LG (quotient, Janz)', \
         f(s) using @U:@V with lines lw 1.0 lc rgb 'black' title SHORT(s)
}
unset multiplot
