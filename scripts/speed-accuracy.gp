# docs/speed-accuracy.csv -> docs/speed-accuracy.png (scripts/chart.sh). Five panels, error
# against time on log scales, one curve per method: lower left is better.
set datafile separator ","
set terminal pngcairo size 1950,1000 font ",10"
set output "docs/speed-accuracy.png.tmp"
set multiplot layout 2,3
set logscale xy
set grid
set format x "10^{%L}"
set format y "10^{%L}"
set key top right font ",9"
csv = "docs/speed-accuracy.csv"
# The rows of one part and method, so that each curve is one connected line.
rows(p, m) = sprintf("< awk -F, '$1==\"%s\" && $2==\"%s\"' %s", p, m, csv)

set title "Point form factors vs Lambert (200 receivers)"
set xlabel "seconds per form factor"
set ylabel "mean |F - F_{exact}| / mean F_{exact}"
plot rows("point-far","hemicube") using 4:5 w lp pt 7 t "hemi-cube R 16-512, distance 1", \
     rows("point-far","ray_cast") using 4:5 w lp pt 5 t "ray cast n 1-256, distance 1", \
     rows("point-near","hemicube") using 4:5 w lp pt 6 t "hemi-cube, distance 0.15", \
     rows("point-near","ray_cast") using 4:5 w lp pt 4 t "ray cast, distance 0.15"

set title "Perturbed radiosity B'(N') vs exact (300 normals, tilt <= 45 deg), by storage"
set xlabel "bytes per map vertex (RGB doubles: 24 per sampled normal or SH coefficient)"
set ylabel "mean |B' - B'_{exact}| / mean B'_{exact}"
set format x "%g"
plot rows("perturbed","gather") using ($3*24):5 w lp pt 7 t "sampled normals, gathered (hemi-cube 150 per vertex)", \
     rows("perturbed","gather") using ($3*24):5:3 w labels offset 0,0.8 font ",8" notitle, \
     rows("perturbed","shoot") using ($3*24):5 w lp pt 5 t "sampled normals, shot (256 shots)", \
     rows("perturbed","gather_sh") using ($3*24):5 w p pt 9 ps 1.5 t "spherical harmonics 0-2+4 (the default), gathered", \
     rows("perturbed","shoot_sh") using ($3*24):5 w p pt 11 ps 1.5 t "spherical harmonics 0-2+4, shot"
set format x "10^{%L}"

set yrange [0.005:2]  # the same scale for the three scenes, 1 % well inside
do for [scene in "cornell wrinkled-box paper-room"] {
  set title sprintf("%s (128 x 128) vs path-traced ground truth", scene)
  set xlabel "seconds to the image (solve and render; path tracer: render)"
  set ylabel "relative RMS error, lit surfaces"
  plot rows(scene,"path_tracer") using 4:5 w lp pt 7 t "path tracer, 1-4096 paths a pixel", \
       rows(scene,"path_tracer") using 4:5:3 w labels offset 0,0.8 font ",8" notitle, \
       rows(scene,"exact") using 4:5 w p pt 5 ps 1.3 t "bumprad, exact direct light (default)", \
       rows(scene,"exact") using 4:5:3 w labels offset 0,-0.8 font ",8" notitle, \
       rows(scene,"radiosity") using 4:5 w p pt 4 ps 1.3 t "bumprad, all light from the radiosity (paper)"
}
unset multiplot
set output
system("mv docs/speed-accuracy.png.tmp docs/speed-accuracy.png")
