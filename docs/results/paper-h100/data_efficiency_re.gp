# data_efficiency_re.png and data_efficiency_re.svg from data_efficiency_re.dat, drawn by eitbench. Edit this script and run `gnuplot data_efficiency_re.gp` in this folder to draw them again.
set title "test RE against training-set size (mean +- standard error over test frames)" noenhanced
set xlabel "training frames (before augmentation)" noenhanced
set ylabel "RE (relative error)" noenhanced
set grid back lc rgb '#dddddd'
set border 3
set tics nomirror
set key outside right top noenhanced
set format x '%g'
set format y '%g'
set logscale x
set xtics (700, 1400, 2800, 5600, 11200, 21833)
set xrange [608.696:25107.9]
plot 'data_efficiency_re.dat' index 0 using 1:2 with linespoints pt 7 ps 0.6 lc rgb '#000000' lw 2 dt 1 title "none, converged", \
     'data_efficiency_re.dat' index 0 using 1:2:3:4 with yerrorbars lc rgb '#000000' lw 2 dt 1 pt 7 ps 0.4 notitle, \
     'data_efficiency_re.dat' index 1 using 1:2 with linespoints pt 7 ps 0.6 lc rgb '#009e73' lw 2 dt 1 title "d16, converged", \
     'data_efficiency_re.dat' index 1 using 1:2:3:4 with yerrorbars lc rgb '#009e73' lw 2 dt 1 pt 7 ps 0.4 notitle, \
     'data_efficiency_re.dat' index 2 using 1:2 with linespoints pt 7 ps 0.6 lc rgb '#009e73' lw 2 dt 2 title "d16, none's steps", \
     'data_efficiency_re.dat' index 2 using 1:2:3:4 with yerrorbars lc rgb '#009e73' lw 2 dt 2 pt 7 ps 0.4 notitle
set terminal pngcairo size 900,560 enhanced font 'DejaVu Sans,10'
set output 'data_efficiency_re.png'
replot
set terminal svg size 900,560 dynamic enhanced font 'DejaVu Sans,10'
set output 'data_efficiency_re.svg'
replot
unset output
