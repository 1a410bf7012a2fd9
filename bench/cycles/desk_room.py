# Writes a bumprad scene of a room it was not tuned for, all quads (so that
# scripts/cycles.sh --scene can build it in Blender as well): 4 x 2.7 x 5 m, a blue wall, a
# 1 m ceiling panel, a 12 cm lamp 0.2 m from a wall over a desk on 4 cm legs, a shelf against
# a wall, a crate turned 30 degrees; every solver setting at its default. Faces point out of
# solids and into the room.
#   python3 bench/cycles/desk_room.py OUT.json
import json
import math
import sys
objs = []
def quad(name, mat, v): objs.append({"name": name, "type": "quad", "material": mat, "vertices": [list(map(float, p)) for p in v]})
def box(name, mat, c, h, rot=0.0, skip_bottom=True):
    # axis-aligned box centre c, half sizes h, rotated rot degrees about y; faces outward
    cx, cy, cz = c; hx, hy, hz = h
    a = math.radians(rot)
    def P(x, y, z):
        dx, dz = x * hx, z * hz
        return (cx + dx * math.cos(a) + dz * math.sin(a), cy + y * hy, cz - dx * math.sin(a) + dz * math.cos(a))
    faces = {
        "top":    [P(-1,1,-1), P(-1,1,1), P(1,1,1), P(1,1,-1)],
        "bottom": [P(-1,-1,-1), P(1,-1,-1), P(1,-1,1), P(-1,-1,1)],
        "xp":     [P(1,-1,-1), P(1,1,-1), P(1,1,1), P(1,-1,1)],
        "xn":     [P(-1,-1,-1), P(-1,-1,1), P(-1,1,1), P(-1,1,-1)],
        "zp":     [P(-1,-1,1), P(1,-1,1), P(1,1,1), P(-1,1,1)],
        "zn":     [P(-1,-1,-1), P(-1,1,-1), P(1,1,-1), P(1,-1,-1)],
    }
    for k, v in faces.items():
        if k == "bottom" and skip_bottom: continue
        quad(f"{name} {k}", mat, v)
W, H, D = 4.0, 2.7, 5.0
# room: faces point inward
quad("floor", "floor", [(0,0,0), (0,0,D), (W,0,D), (W,0,0)])
quad("ceiling", "white", [(0,H,0), (W,H,0), (W,H,D), (0,H,D)])
quad("back wall", "white", [(0,0,D), (0,H,D), (W,H,D), (W,0,D)])
quad("left wall", "blue", [(0,0,0), (0,H,0), (0,H,D), (0,0,D)])
quad("right wall", "white", [(W,0,0), (W,0,D), (W,H,D), (W,H,0)])
quad("front wall", "white", [(0,0,0), (W,0,0), (W,H,0), (0,H,0)])
# ceiling panel facing down, 1 cm below the ceiling
quad("panel", "panel", [(1.5,H-0.01,2.0), (2.5,H-0.01,2.0), (2.5,H-0.01,3.0), (1.5,H-0.01,3.0)])
# desk against the right wall: top 1.4 x 0.7 at 0.75 m, legs 4 cm
box("desk top", "wood", (3.45, 0.74, 3.6), (0.35, 0.02, 0.7), skip_bottom=False)
for i, (lx, lz) in enumerate([(3.14, 2.94), (3.76, 2.94), (3.14, 4.26), (3.76, 4.26)]):
    box(f"leg {i}", "wood", (lx, 0.36, lz), (0.02, 0.36, 0.02))
# small lamp over the desk, near the wall, facing down
quad("lamp", "lamp", [(3.7,1.3,3.5), (3.82,1.3,3.5), (3.82,1.3,3.62), (3.7,1.3,3.62)])
# shelf against the left wall
box("shelf", "wood", (0.15, 1.0, 2.5), (0.15, 1.0, 0.6))
# crate rotated 30 degrees
box("crate", "crate", (1.4, 0.3, 3.6), (0.3, 0.3, 0.3), rot=30)
s = {"version": 1,
     "camera": {"position": [0.6, 1.6, 0.3], "look_at": [2.6, 0.9, 3.6], "up": [0,1,0], "fov_deg": 60, "width": 256, "height": 192, "antialias": 2},
     "materials": {"floor": {"reflectance": [0.55, 0.5, 0.45]}, "white": {"reflectance": 0.75}, "blue": {"reflectance": [0.2, 0.3, 0.6]},
                   "wood": {"reflectance": [0.5, 0.35, 0.2]}, "crate": {"reflectance": [0.6, 0.55, 0.3]},
                   "panel": {"reflectance": 0.8, "emission": 20}, "lamp": {"reflectance": 0.8, "emission": 400}},
     "objects": objs}
with open(sys.argv[1], "w") as f:
    json.dump(s, f, indent=1)
