# Shared by the study's figures: called as gnuplot -e "data='DIR'; out='FILE'; quick=0|1" X.gp
set terminal pngcairo size 1500,960 font ',10' noenhanced
set output out
set grid lc rgb '#dddddd'
set border lc rgb '#444444'
set key box opaque samplen 2 spacing 1.0 font ',8'
scenes = quick ? "neo_hookean lj_two_body" : \
         "neo_hookean lj_two_body lj_cluster8 solar_system hanging_chain"
methods = quick ? "mp lg pm verlet gsl-rk2imp gsl-rk4imp gsl-rk4" : \
          "mp lg lgq ge pm pt verlet euler gsl-rk2imp gsl-rk4imp gsl-rk4"
colour(m) = m eq "mp" ? "#1f4fd1" : m eq "lg" ? "#d12f1f" : m eq "lgq" ? "#f08080" : \
            m eq "ge" ? "#2a9d3a" : m eq "pm" ? "#000000" : m eq "pt" ? "#c07a00" : \
            m eq "verlet" ? "#8e44ad" : m eq "euler" ? "#999999" : m eq "rk4" ? "#16a085" : \
            m eq "gsl-rk2imp" ? "#2980b9" : m eq "gsl-rk4imp" ? "#e67e22" : "#16a085"
edmi(m) = m eq "mp" || m eq "lg" || m eq "lgq" || m eq "ge" || m eq "pm" || m eq "pt"
dat(s, m, p) = data . '/dat/' . s . '_' . m . '_' . p . '.dat'
set logscale xy
set format x '1e%T'
set format y '1e%T'
