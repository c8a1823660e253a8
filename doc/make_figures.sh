#!/usr/bin/env bash
# Regenerates the figures of README.md and doc/ from the decks in parameters/
# (needs the build and gnuplot: ./setup.sh run builds, gnuplot-nox plots).
set -euo pipefail
cd "$(dirname "$0")/.."
program=./build/dieflow
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# variant DECK NAME OUTPUTS [SED ARGS]: DECK as $work/NAME.prm, writing into
# $work/NAME, with its "set Write VTU" line replaced by OUTPUTS.
variant() {
  local deck=$1 name=$2 outputs=$3
  shift 3
  sed -e "s|^set Output directory.*|set Output directory = $work/$name|" \
      -e "s|^set Write VTU .*|$outputs|" "$@" "$deck" > "$work/$name.prm"
}

# The speed of the default deck, die2d (the metal leaving the die at D).
variant parameters/die2d.prm die2d 'set Write VTU = false\nset Write gnuplot = true'
$program "$work/die2d.prm" > /dev/null
gnuplot <<GP
set terminal pngcairo size 1200,480 font "sans,11"
set output 'doc/images/die2d-speed.png'
set view map
set size ratio -1
set palette rgbformulae 33,13,10
set xlabel 'x (mm)'
set ylabel 'y (mm)'
set cblabel 'speed |v| (mm/s)'
set title 'die2d (parameters/die2d.prm): speed; ram at 190 mm/s from the left, die face and land at the top right'
splot '$work/die2d/solution-00.gnuplot' using 1:2:(sqrt(\$3**2+\$4**2)) with pm3d notitle
GP
echo "wrote doc/images/die2d-speed.png"

# The mesh of an adaptive study of die2d N1 after eight cycles (needs
# rsvg-convert, from Debian's librsvg2-bin, to turn the program's SVG into PNG).
if command -v rsvg-convert > /dev/null; then
  variant parameters/die2d-held-land.prm adaptive 'set Write VTU = false\nset Write mesh SVG = true'
  cat >> "$work/adaptive.prm" <<DECK
subsection Mesh
  subsection Die2d
    set Cells across = 4
  end
end
subsection Refinement
  set Cycles          = 9
  set Strategy        = adaptive
  set Indicator       = kelly
  set Marking         = fixed number
  set Refine fraction = 0.3
end
DECK
  $program "$work/adaptive.prm" > /dev/null
  rsvg-convert -w 1000 "$work/adaptive/mesh-08.svg" -o doc/images/die2d-adaptive-mesh.png
  echo "wrote doc/images/die2d-adaptive-mesh.png"
fi

# Wire drawing: the drawing stress against the die semi-angle (doc/axisymmetric.md).
python3 benchmarks/drawing_stress.py --program "$program" --curve 0.05 > "$work/drawing.dat"
gnuplot <<GP
set terminal pngcairo size 900,560 font "sans,11"
set output 'doc/images/drawing-stress.png'
set xlabel 'die semi-angle alpha (degrees)'
set ylabel 'drawing stress sigma_d / sigma_0'
set title 'Wire drawing, 20 % reduction, Coulomb mu = 0.05 (parameters/wiredrawing.prm)'
set key top left
set grid
plot '$work/drawing.dat' using 1:4 with lines lw 2 title 'Avitzur upper bound (m_f = sqrt(3) mu)', \
     '' using 1:5 with linespoints lw 2 pt 7 title 'dieflow (Norton-Hoff m = 0.05)', \
     '' using 1:3 with lines lw 2 title 'Sachs slab method', \
     '' using 1:2 with lines lw 2 dt 2 title 'ideal work ln(A_0/A_f)'
GP
echo "wrote doc/images/drawing-stress.png"

# The ring test's calibration curves (doc/incremental.md): the change of the
# inner diameter against the reduction, Avitzur's upper bound and the program
# (parameters/ring-compression.prm with a Tresca friction factor m).
python3 benchmarks/ring_upper_bound.py --program "$program" --curves "$work/ring.dat" > /dev/null
gnuplot <<GP
set terminal pngcairo size 900,620 font "sans,11"
set output 'doc/images/ring-calibration.png'
set xlabel 'height reduction (%)'
set ylabel 'change of the inner diameter (%)'
set title 'Ring compression 6:3:2 (parameters/ring-compression.prm): calibration curves, friction factor m'
set key top left
set grid
set xrange [0:50]
set style line 1 lc rgb '#1f77b4' lw 2
set style line 2 lc rgb '#2ca02c' lw 2
set style line 3 lc rgb '#ff7f0e' lw 2
set style line 4 lc rgb '#d62728' lw 2
plot for [i=0:3] '$work/ring.dat' index i using 1:2 with lines ls (i+1) dt 2 title sprintf('upper bound, m = %s', word("0 0.1 0.2 0.4", i+1)), \
     for [i=0:3] '' index i using 1:3 every 2 with linespoints ls (i+1) pt 7 ps 0.6 title sprintf('dieflow, m = %s', word("0 0.1 0.2 0.4", i+1))
GP
echo "wrote doc/images/ring-calibration.png"

# A genuinely 3D die (doc/three-dimensional.md): the contact pressure and the
# stick / slip / separated map on the two die walls of parameters/rectbar3d.prm,
# each wall unrolled onto its own plane (the y wall seen along y, the z wall
# along z; x the drawing direction).
variant parameters/rectbar3d.prm rectbar3d 'set Write VTU = false'
$program "$work/rectbar3d.prm" > /dev/null
r="$work/rectbar3d"
gnuplot <<GP
set terminal pngcairo size 1300,820 font "sans,11"
set output 'doc/images/rectbar3d-contact.png'
set multiplot layout 2,2 title 'parameters/rectbar3d.prm: 38 x 20 mm bar drawn to 9.5 x 12 mm (die 70 degrees in y, 37.6 degrees in z, mu = 0.1), quarter model'
set size ratio -1
set xrange [-20:21]
set xlabel 'x (mm)'
set palette rgbformulae 33,13,10
set cblabel 'contact pressure (MPa)'
# The die-exit line (the re-entrant corner, singular) carries 1,900-2,050 MPa: off the scale.
set cbrange [0:600]
set ylabel 'z (mm)'
set title 'y walls (container y = 19, die face and land): contact pressure'
plot '$r/die-surface-3.dat' using 1:3:4 with points pt 5 ps 1.4 palette notitle, \
     '$r/die-surface-4.dat' using 1:3:4 with points pt 5 ps 1.4 palette notitle
set ylabel 'y (mm)'
set title 'z walls (container z = 10, die face and land): contact pressure'
plot '$r/die-surface-6.dat' using 1:2:4 with points pt 5 ps 1.4 palette notitle, \
     '$r/die-surface-7.dat' using 1:2:4 with points pt 5 ps 1.4 palette notitle
unset colorbox
set palette defined (0 'grey70', 1 'blue', 2 'red')
set cbrange [0:2]
set ylabel 'z (mm)'
set title 'y walls: separated (grey), stick (blue), slip (red)'
plot '$r/die-surface-3.dat' using 1:3:(\$13) with points pt 5 ps 1.4 palette notitle, \
     '$r/die-surface-4.dat' using 1:3:(\$13) with points pt 5 ps 1.4 palette notitle
set ylabel 'y (mm)'
set title 'z walls: separated (grey), stick (blue), slip (red)'
plot '$r/die-surface-6.dat' using 1:2:(\$13) with points pt 5 ps 1.4 palette notitle, \
     '$r/die-surface-7.dat' using 1:2:(\$13) with points pt 5 ps 1.4 palette notitle
unset multiplot
GP
echo "wrote doc/images/rectbar3d-contact.png"

# Forming in time (doc/incremental.md): the load-stroke curve of
# parameters/upsetting-incremental.prm against the slab estimate, and the
# barrelled mesh at 50 % reduction.
variant parameters/upsetting-incremental.prm upsetting 'set Write VTU = false\nset Write gnuplot = true'
$program "$work/upsetting.prm" > /dev/null
gnuplot <<GP
set terminal pngcairo size 1300,520 font "sans,11"
set output 'doc/images/upsetting-load-stroke.png'
set multiplot layout 1,2
set title 'platen force against stroke (parameters/upsetting-incremental.prm)'
set xlabel 'height reduction (%)'
set ylabel 'platen force F (kN)'
set key top left
# Slab estimate: F = sigma_0 pi a^2 (1 + 2 mu a / (3 h)), volume kept (a^2 h = 100 x 10),
# sigma_0 = K (V/h)^m with V = 10 mm/s closing speed, h = 10 - 10 t.
h(s) = 10 - 2*s
slab(s) = (10/h(s))**0.05 * pi * 1000/h(s) * (1 + 2*0.2*sqrt(1000/h(s))/(3*h(s))) / 1000
plot '$work/upsetting/load-stroke.txt' using (100*\$3/5):(\$4/1000) with linespoints pt 7 ps 0.5 title 'dieflow, Coulomb mu = 0.2', \
     [0:2.5] '+' using (100*\$1/5):(slab(\$1)) with lines dt 2 lw 2 title 'slab estimate 1 + 2 mu a / (3 h)'
set title 'mesh at 50 % reduction (the platen moved down to x = 2.5 mm; a new mesh at 39 %)'
set xlabel 'r (mm)'
set ylabel 'x (mm)'
set xrange [0:16]
set view map
set size ratio -1
unset key
unset colorbox
splot '$work/upsetting/solution-50.gnuplot' using 2:1:(0) with lines lc rgb '#404040'
unset multiplot
GP
echo "wrote doc/images/upsetting-load-stroke.png"

# The start of the die2d extrusion (doc/incremental.md): the ram force per
# step against the stroke, with the limit of the steady run with its free
# surface (N0, degree 2 to 64 cells across: about 2158 N/mm), and the mesh
# at the end.
variant parameters/extrusion-start.prm extrusion 'set Write VTU = false\nset Write gnuplot = true' \
        -e "s|die2d-die-face-land.msh|$PWD/parameters/die2d-die-face-land.msh|"
$program "$work/extrusion.prm" > /dev/null
gnuplot <<GP
set terminal pngcairo size 1300,520 font "sans,11"
set output 'doc/images/extrusion-start-load-stroke.png'
set multiplot layout 1,2
set title 'ram force per step (parameters/extrusion-start.prm, frictionless)'
set xlabel 'ram stroke (mm)'
set ylabel 'ram force F_x[1] (N/mm)'
set yrange [0:3000]
set key bottom right
plot '$work/extrusion/load-stroke.txt' using 3:4 with linespoints pt 7 ps 0.5 title 'in time (the front leaves the land at 3.8 mm)', \
     2158 with lines dt 2 lw 2 title 'steady run with its free surface: limit (degree 2, to 64 cells across)'
set title 'the mesh at the end (stroke 7.6 mm); the die face and land in red'
set xlabel 'x (mm)'
set ylabel 'y (mm)'
set xrange [-8:40]
set yrange [0:20]
set size ratio -1
unset key
plot '$work/extrusion/solution-100.gnuplot' using 1:2 with lines lc rgb '#404040', \
     '-' using 1:2 with lines lw 3 lc rgb 'red'
0 19
5.186575838293384 4.75
20.186575838293384 4.75
e
unset multiplot
GP
echo "wrote doc/images/extrusion-start-load-stroke.png"
