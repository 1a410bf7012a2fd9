# docs/speed-accuracy.csv -> docs/speed-accuracy.png (scripts/chart.sh). Five panels, error
# against time on log scales, one curve per method: lower left is better.
set datafile separator ","
set terminal pngcairo size 1300,1400 font ",10"
set output "docs/speed-accuracy.png.tmp"
set multiplot layout 3,2
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

set title "Perturbed radiosity B'(N') vs exact (300 normals, tilt <= 45 deg)"
set xlabel "seconds of texture work per map vertex"
set ylabel "mean |B' - B'_{exact}| / mean B'_{exact}"
plot rows("perturbed","gather") using 4:5:3 w lp pt 7 t "gather (hemi-cube 150 per vertex)", \
     rows("perturbed","gather") using 4:5:3 w labels offset 0,0.8 font ",8" notitle, \
     rows("perturbed","shoot") using 4:5:3 w lp pt 5 t "shoot (with 256 shots)", \
     rows("perturbed","shoot") using 4:5:3 w labels offset 0,-0.8 font ",8" notitle

do for [scene in "cornell wrinkled-box"] {
  set title sprintf("%s: image vs hemi-cube 512 reference", scene)
  set xlabel "solve seconds (to 0.2% unshot)"
  set ylabel "mean |I - I_{ref}| / mean I_{ref}"
  plot rows(scene,"hemicube_alias_0") using 4:5 w lp pt 7 t "hemi-cube R 32-250", \
       rows(scene,"hemicube_alias_1") using 4:5 w lp pt 6 t "+ ray-cast fallback < 1 pixel (default)", \
       rows(scene,"hemicube_alias_4") using 4:5 w lp pt 4 t "+ fallback < 4 pixels", \
       rows(scene,"ray_cast") using 4:5 w p pt 5 ps 1.5 t "ray cast, 16 samples per patch"
}
set title "cornell: elements vs image error (reference: elements of half the default size)"
set xlabel "elements"
set ylabel "mean |I - I_{ref}| / mean I_{ref}"
set format x "%g"
plot rows("elements","uniform") using 3:5 w lp pt 7 t "uniform, element size 2x to 0.75x the default", \
     rows("elements","adaptive") using 3:5 w lp pt 5 t "adaptive from 2x, 1 and 2 levels"
unset multiplot
set output
system("mv docs/speed-accuracy.png.tmp docs/speed-accuracy.png")
