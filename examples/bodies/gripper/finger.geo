// A gripper finger: an LCE layer (top, director along the finger) on a passive Kapton backing
// (bottom), with a serpentine heater track (four legs along the finger and their three turns)
// through the LCE layer; the base x = 0 is clamped. Free tetrahedra, size 2.4 mm times
// [mesh] size_factor (1: 767 cells, the gallery test's coarse level; 0.5: 5870). Units: mm.
// Cells "lce" (the LCE outside the track), "coil" (the LCE the track heats), "kapton";
// facets "base" (x = 0), "surface" (every other outer face), "tip" (x = L).
SetFactory("OpenCASCADE");

L = 30;     // finger length [mm]
W = 10;     // width [mm]
t = 1.0;    // LCE layer [mm]
tk = 0.125; // Kapton backing [mm] (Kapton HN 500, 125 um)
w = 1.0;    // track width [mm]
x0 = 3; x1 = 27;                 // the legs run from x0 to x1 [mm]
ys[] = {1.5, 3.5, 5.5, 7.5};     // the legs' lower edges [mm]

Box(1) = {0, 0, 0, L, W, t};       // LCE
Box(2) = {0, 0, -tk, L, W, tk};    // Kapton
n = #ys[];
For i In {0:n - 1}
  Box(10 + i) = {x0, ys[i], 0, x1 - x0, w, t};
EndFor
For i In {0:n - 2}  // turns: alternately at the far and the near end
  xt = (i % 2 == 0) ? x1 - w : x0;
  Box(20 + i) = {xt, ys[i], 0, w, ys[i + 1] - ys[i] + w, t};
EndFor
coil() = BooleanUnion{ Volume{10}; Delete; }{ Volume{11:10 + n - 1, 20:20 + n - 2}; Delete; };
out() = BooleanFragments{ Volume{1, 2}; Delete; }{ Volume{coil()}; Delete; };

e = 1e-4;
kap() = Volume In BoundingBox{-e, -e, -tk - e, L + e, W + e, e};
lce_all() = Volume In BoundingBox{-e, -e, -e, L + e, W + e, t + e};
track() = Volume In BoundingBox{x0 - e, ys[0] - e, -e, x1 + e, ys[n - 1] + w + e, t + e};
Physical Volume("coil", 1) = {track()};
Physical Volume("lce", 2) = {lce_all()};
Physical Volume("lce", 2) -= {track()};
Physical Volume("kapton", 3) = {kap()};

base() = Surface In BoundingBox{-e, -e, -tk - e, e, W + e, t + e};
tip() = Surface In BoundingBox{L - e, -e, -tk - e, L + e, W + e, t + e};
all() = Abs(CombinedBoundary{ Volume{:}; });
Physical Surface("base", 1) = {base()};
Physical Surface("tip", 2) = {tip()};
Physical Surface("surface", 3) = {all()};
Physical Surface("surface", 3) -= {base()};

Mesh.MeshSizeMax = 2.4 * Mesh.MeshSizeFactor;
Mesh.MeshSizeMin = 0.1;
