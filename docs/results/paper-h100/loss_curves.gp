# loss_curves.png and loss_curves.svg from loss_curves.dat, drawn by eitbench. Edit this script and run `gnuplot loss_curves.gp` in this folder to draw them again.
set title "MSE against samples seen: training (dashed) and validation" noenhanced
set xlabel "training samples seen" noenhanced
set ylabel "MSE (per pixel)" noenhanced
set grid back lc rgb '#dddddd'
set border 3
set tics nomirror
set key outside right top noenhanced
set format x '%g'
set format y '%g'
set logscale y
set mytics 10
plot 'loss_curves.dat' index 0 using 1:2 with lines lc rgb '#000000' lw 2 dt 2 title "none training", \
     'loss_curves.dat' index 1 using 1:2 with lines lc rgb '#000000' lw 2 dt 1 title "none validation", \
     'loss_curves.dat' index 2 using 1:2 with lines lc rgb '#17becf' lw 2 dt 2 title "rotations training", \
     'loss_curves.dat' index 3 using 1:2 with lines lc rgb '#17becf' lw 2 dt 1 title "rotations validation", \
     'loss_curves.dat' index 4 using 1:2 with lines lc rgb '#009e73' lw 2 dt 2 title "d16 training", \
     'loss_curves.dat' index 5 using 1:2 with lines lc rgb '#009e73' lw 2 dt 1 title "d16 validation", \
     'loss_curves.dat' index 6 using 1:2 with lines lc rgb '#9467bd' lw 2 dt 2 title "paper training", \
     'loss_curves.dat' index 7 using 1:2 with lines lc rgb '#9467bd' lw 2 dt 1 title "paper validation"
set terminal pngcairo size 900,560 enhanced font 'DejaVu Sans,10'
set output 'loss_curves.png'
replot
set terminal svg size 900,560 dynamic enhanced font 'DejaVu Sans,10'
set output 'loss_curves.svg'
replot
unset output
