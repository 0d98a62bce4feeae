# touch_centre_errors.png and touch_centre_errors.svg from touch_centre_errors.dat, drawn by eitbench. Edit this script and run `gnuplot touch_centre_errors.gp` in this folder to draw them again.
set title "share of true touches found within a centre distance, 40 dB" noenhanced
set xlabel "centre error (x R, the sensor radius)" noenhanced
set ylabel "share of true touches" noenhanced
set grid back lc rgb '#dddddd'
set border 3
set tics nomirror
set key outside right top noenhanced
set format x '%g'
set format y '%g'
plot 'touch_centre_errors.dat' index 0 using 1:2 with lines lc rgb '#7f7f7f' lw 2 dt 1 title "tikhonov", \
     'touch_centre_errors.dat' index 1 using 1:2 with lines lc rgb '#e69f00' lw 2 dt 1 title "noser", \
     'touch_centre_errors.dat' index 2 using 1:2 with lines lc rgb '#56b4e9' lw 2 dt 1 title "laplace", \
     'touch_centre_errors.dat' index 3 using 1:2 with lines lc rgb '#b8860b' lw 2 dt 1 title "greit", \
     'touch_centre_errors.dat' index 4 using 1:2 with lines lc rgb '#000000' lw 2 dt 1 title "dnn (none)", \
     'touch_centre_errors.dat' index 5 using 1:2 with lines lc rgb '#17becf' lw 2 dt 1 title "dnn (rotations)", \
     'touch_centre_errors.dat' index 6 using 1:2 with lines lc rgb '#009e73' lw 2 dt 1 title "dnn (d16)", \
     'touch_centre_errors.dat' index 7 using 1:2 with lines lc rgb '#9467bd' lw 2 dt 1 title "dnn (paper)"
set terminal pngcairo size 900,560 enhanced font 'DejaVu Sans,10'
set output 'touch_centre_errors.png'
replot
set terminal svg size 900,560 dynamic enhanced font 'DejaVu Sans,10'
set output 'touch_centre_errors.svg'
replot
unset output
