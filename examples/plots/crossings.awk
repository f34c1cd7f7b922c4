# The angular frequency of a trace from the upward zero crossings of column `col` minus x0,
# each placed by linear interpolation between its two rows (make_plots.sh):
#   awk -v col=C -v x0=X -f examples/plots/crossings.awk TRACE.csv
BEGIN { FS = ","; n = 0 }
NR > 1 {
    u = $col - x0
    if (NR > 2 && prev < 0 && u >= 0) {
        tc = tprev + ($1 - tprev) * prev / (prev - u)
        if (n == 0)
            t0 = tc
        t1 = tc
        n++
    }
    prev = u; tprev = $1
}
END { printf "%.12g\n", (n > 1 ? 2 * atan2(0, -1) * (n - 1) / (t1 - t0) : 0) }
