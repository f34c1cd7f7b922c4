# Shared settings for the edmi figures. Every script is called as
#   gnuplot -e "data='DIR'; out='FILE.png'" SCRIPT.gp
# where DIR holds the CSV traces of examples/plots/make_plots.sh. CSV columns (1-based):
#   1 t, 2 H, 3 (H-H0)/|H0|, 4-6 J, 7-9 L, 10-12 C, 13 |J-J0|, 14 |L-L0|, 15 |C-C0|,
#   16 Newton iterations, 17 W_ext, 18 D_scheme, 19 D_damping (sums from t = 0),
#   then per body b = 0, 1, ...: 20+6b..22+6b q, 23+6b..25+6b p.
set datafile separator ','
set datafile columnheaders
set grid lc rgb '#dddddd'
set border lc rgb '#444444'
set key box opaque samplen 2 spacing 1.1
qx(b) = column(20 + 6 * b)
qy(b) = column(21 + 6 * b)
qz(b) = column(22 + 6 * b)
# schemes: file suffix, title, colour, dash (MP blue dashed, LG red dash-dot as in the paper)
S = "mp lg ge pm pt"
TITLE(s) = s eq "mp" ? "MP mid-point" : s eq "lg" ? "LG LaBudde-Greenspan" : \
           s eq "ge" ? "GE generalized Eyre" : s eq "pm" ? "PM perturbed mid-point" : \
           "PT perturbed trapezoidal"
SHORT(s) = s eq "mp" ? "MP" : s eq "lg" ? "LG" : s eq "ge" ? "GE" : s eq "pm" ? "PM" : "PT"
COLOR(s) = s eq "mp" ? "#1f4fd1" : s eq "lg" ? "#d12f1f" : s eq "ge" ? "#2a9d3a" : \
           s eq "pm" ? "#000000" : "#c07a00"
