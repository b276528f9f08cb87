// An LCE bilayer: an LCE layer (bottom, director along x) bonded to a passive layer of the same
// Young's modulus (top), a quarter of a 40 mm x 2 mm x 1 mm beam: x in [0, 20] (x = 0 the
// mid-length mirror plane), y in [0, 1] (y = 0 the mid-width mirror plane), z in [0, 1] (z = 0.5
// the bond). Structured hexahedra; [mesh] size_factor s multiplies every edge's divisions by 1/s.
// Cells "lce", "top"; facets "sym_x" (x = 0), "sym_y" (y = 0), "tip" (x = 20). Units: mm.
SetFactory("OpenCASCADE");

Lh = 20;    // half length [mm]
bh = 1;     // half width [mm]
h1 = 0.5;   // LCE layer [mm]
h2 = 0.5;   // passive layer [mm]
m = 1 / Mesh.MeshSizeFactor;  // 2 m divisions on each short edge (the 1 mm half width, each 0.5 mm
                              // layer), 20 m along; rounded, at least one (size factor 2: 20 cells)

Box(1) = {0, 0, 0, Lh, bh, h1};
Box(2) = {0, 0, h1, Lh, bh, h2};
BooleanFragments{ Volume{1:2}; Delete; }{}

e = 1e-4;
Transfinite Curve{ Curve In BoundingBox{-e, -e, -e, Lh + e, bh + e, h1 + h2 + e} } = Max(1, Round(2 * m)) + 1;
zs[] = {0, h1, h1 + h2};
For j In {0:2}  // the axial edges: 20 m divisions (1/m mm)
  Transfinite Curve{ Curve In BoundingBox{-e, -e, zs[j] - e, Lh + e, e, zs[j] + e} } = Max(1, Round(20 * m)) + 1;
  Transfinite Curve{ Curve In BoundingBox{-e, bh - e, zs[j] - e, Lh + e, bh + e, zs[j] + e} } = Max(1, Round(20 * m)) + 1;
EndFor
Transfinite Surface{:};
Recombine Surface{:};
Transfinite Volume{:};
Recombine Volume{:};

Physical Volume("lce", 1) = Volume In BoundingBox{-e, -e, -e, Lh + e, bh + e, h1 + e};
Physical Volume("top", 2) = Volume In BoundingBox{-e, -e, h1 - e, Lh + e, bh + e, h1 + h2 + e};
Physical Surface("sym_x", 1) = Surface In BoundingBox{-e, -e, -e, e, bh + e, h1 + h2 + e};
Physical Surface("sym_y", 2) = Surface In BoundingBox{-e, -e, -e, Lh + e, e, h1 + h2 + e};
Physical Surface("tip", 3) = Surface In BoundingBox{Lh - e, -e, -e, Lh + e, bh + e, h1 + h2 + e};
