# Time against N, log-log (bench/run.sh): gnuplot -e "data='...'; svg='...'; txt='...'" plot.gp
# Columns of the data (bench/report.py): N, nhc derive+analyse+generate, nhc compile,
# nhc integrate, hand-written integrate, SymPy derive+lambdify, SciPy Radau, SciPy BDF.
set logscale xy
set xlabel "N (knife edges; 7N states)"
set ylabel "wall time [s]"
set key below
set grid
set xrange [0.8:80]
set format y "%g"
plot data u 1:2 w lp pt 7 lc rgb "#1f77b4" t "nhc derive+analyse+generate", \
     data u 1:3 w lp pt 5 lc rgb "#aec7e8" t "nhc compile (g++ -O2)", \
     data u 1:4 w lp pt 9 lc rgb "#2ca02c" t "nhc integrate (IDA)", \
     data u 1:5 w lp pt 8 lc rgb "#98df8a" t "hand-written integrate (IDA)", \
     data u 1:6 w lp pt 11 lc rgb "#d62728" t "SymPy derive+lambdify", \
     data u 1:7 w lp pt 13 lc rgb "#ff7f0e" t "SciPy Radau", \
     data u 1:8 w lp pt 15 lc rgb "#9467bd" t "SciPy BDF"
