# The seed report's Fig. 5, reproduced: docs/fig5.csv (written by xpbd-fig5)
# -> docs/fig5.png. Run from the repository root: gnuplot docs/fig5.gp
# (scripts/fig5.sh does everything). Columns of the CSV:
#   1 method, 2 iterations, 3 t_s, 4 centre_y_m, 5 lowest_y_m,
#   6 strain_mean, 7 strain_max, 8 bend_mean_rad
set terminal pngcairo size 1200,820 font "Sans,11"
set output "docs/fig5.png"
set datafile separator ","

iters = "5 10 20 50 100"
colors = "#1b9e77 #d95f02 #7570b3 #e7298a #444444"
# Column c of the rows of method m at i iterations; NaN elsewhere (skipped).
sel(m, i, c) = (strcol(1) eq m && column(2) == i) ? column(c) : NaN
# XPBD curves coincide: dash patterns keep all five visible.
dash(k) = k == 5 ? 1 : k + 1

set multiplot layout 2,2 title "Hanging cloth (10 x 10, pinned at two corners, 1 substep per 1/60 s): \
PBD (k = 1) vs XPBD (0.04 m/N) at 5 to 100 iterations" font "Sans,13"
set grid
set xrange [0:3]
set lmargin 10

set ylabel "height of the centre particle (m)"
set yrange [-1.1:0.05]
set key bottom left title "iterations"
set title "PBD"
plot for [k=1:5] "docs/fig5.csv" using 3:(sel("PBD", int(word(iters,k)), 4)) \
     with lines lw 2 lc rgb word(colors,k) title word(iters,k)
set title "XPBD"
set key top right
plot for [k=5:1:-1] "docs/fig5.csv" using 3:(sel("XPBD", int(word(iters,k)), 4)) \
     with lines lw 2 dt dash(k) lc rgb word(colors,k) title word(iters,k)

set xlabel "time (s)"
set ylabel "mean edge strain |l/l0 - 1|"
set logscale y
set yrange [1e-4:0.3]
set format y "10^{%L}"
set key top right title "iterations"
unset title
plot for [k=1:5] "docs/fig5.csv" using 3:(sel("PBD", int(word(iters,k)), 6)) \
     with lines lw 2 lc rgb word(colors,k) title word(iters,k)
set key bottom right title "iterations"
plot for [k=5:1:-1] "docs/fig5.csv" using 3:(sel("XPBD", int(word(iters,k)), 6)) \
     with lines lw 2 dt dash(k) lc rgb word(colors,k) title word(iters,k)
unset multiplot
