# Speedup plot of bench/cell_study.sh. Variables (gnuplot -e): datadir, outfile, kind
# ("modeled": cellsim cycle model; "measured": host wall clock on the study machine's cores).
if (!exists("kind")) kind = "modeled"
if (strstrt(GPVAL_TERMINALS, "pngcairo") > 0) {
  set terminal pngcairo size 900,600 font "sans,11"
} else {
  set terminal png size 900,600
}
set output outfile
set datafile missing "NaN"
set key top left Left reverse opaque box font ",9"
set grid
set logscale x 2
set xrange [0.9:145]
set xtics (1, 2, 4, 8, 16, 32, 64, 128)
set xlabel "SPEs (cell back end)"
f = datadir."/".kind.".dat"
if (kind eq "modeled") {
  set title "Cell back end speedup, modeled (cellsim cycle model)"
  set ylabel "modeled speedup = cycles(1 SPE) / cycles(N)"
  set logscale y 2
  set yrange [0.9:145]
  set ytics (1, 2, 4, 8, 16, 32, 64, 128)
  plot f using 1:2 with lines dashtype 2 lc rgb "gray40" title "ideal", \
       f using 1:3 with linespoints pt 7 title "fandisk default criteria", \
       f using 1:4 with linespoints pt 5 title "fandisk topology only", \
       f using 1:5 with linespoints pt 9 lw 2 title "blade3 default criteria", \
       f using 1:6 with linespoints pt 11 title "blade3 topology only", \
       f using 1:7 with linespoints pt 13 dashtype 3 title "blade3 default criteria, --schedule free", \
       f using 1:8 with linespoints pt 6 lc rgb "dark-red" dashtype 4 title "blade3 default criteria, pass 1 only", \
       f using 1:9 with linespoints pt 4 lc rgb "dark-blue" dashtype 4 title "blade3 --schedule free, pass 1 only"
} else {
  set title "Cell back end speedup, measured: host wall clock on 2 host cores (all SPEs share them)"
  set ylabel "measured wall-clock speedup (2 host cores)"
  set yrange [0:2.5]
  plot f using 1:($1 < 2 ? $1 : 2) with lines dashtype 2 lc rgb "gray40" title "ideal on 2 host cores", \
       f using 1:3 with linespoints pt 7 title "fandisk default criteria", \
       f using 1:4 with linespoints pt 5 title "fandisk topology only", \
       f using 1:5 with linespoints pt 9 title "blade3 default criteria", \
       f using 1:6 with linespoints pt 11 title "blade3 topology only", \
       f using 1:7 with linespoints pt 13 dashtype 3 title "blade3 default criteria, --schedule free"
}
