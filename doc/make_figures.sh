#!/usr/bin/env bash
# Regenerates the figures of README.md and doc/ from the decks in parameters/
# (needs the build and gnuplot: ./setup.sh run builds, gnuplot-nox plots).
set -euo pipefail
cd "$(dirname "$0")/.."
program=./build/dieflow
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# The speed of the default deck, die2d.
sed -e "s|^set Output directory.*|set Output directory = $work/die2d|" \
    -e "s|^set Write VTU .*|set Write VTU = false\nset Write gnuplot = true|" parameters/die2d.prm > "$work/die2d.prm"
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
  sed -e "s|^set Output directory.*|set Output directory = $work/adaptive|" \
      -e "s|^set Write VTU .*|set Write VTU = false\nset Write mesh SVG = true|" parameters/die2d.prm > "$work/adaptive.prm"
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
