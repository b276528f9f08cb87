// The free LCE strip of seed 001 (Fig. 2) in its as-built nematic state, the quarter y <= W/2,
// z <= H/2, with the same geometry, structured hexahedra and tags as lcefem's built-in strip
// (meshes/strip.py, quarter symmetry): cells "lce", "coil"; facets "clamp" (x = 0), "end" (x = L),
// "sides" (outer faces), "sym_y" (y = W/2), "sym_z" (z = H/2). Units: mm.
//
// The size factor ([mesh] size_factor = 1 / (level + 1)) multiplies every edge's division count
// by m = 1 / size_factor, as the built-in strip's mesh level does (level l <-> m = l + 1).
SetFactory("OpenCASCADE");

lambda_N = 1.426;          // nematic stretch: 1 + gamma_1 of Eq. 1 (seed 001), models/empirical.py
L_iso = 80;                // isotropic active length [mm] (seed 001)
W = 5 / Sqrt(lambda_N);    // as-built width [mm] (cast 5 mm)
H = 2 / Sqrt(lambda_N);    // as-built thickness [mm] (cast 2 mm)
L = L_iso * lambda_N;      // as-built length [mm]
c = Sqrt(Pi) / 2 * 1 / Sqrt(lambda_N);  // coil square side [mm]: the 1 mm rod's disc area
size = 2;                  // level-0 element size [mm] (StripMesh.size)
aspect = 4;                // axial element aspect (StripMesh.axial_aspect)
m = Round(1 / Mesh.MeshSizeFactor);

ys[] = {0, (W - c) / 2, W / 2};
zs[] = {0, (H - c) / 2, H / 2};
b = 0;
For j In {0:1}
  For k In {0:1}
    b += 1;
    Box(b) = {0, ys[j], zs[k], L, ys[j + 1] - ys[j], zs[k + 1] - zs[k]};
  EndFor
EndFor
BooleanFragments{ Volume{1:4}; Delete; }{}

e = 1e-4 * H;  // search tolerance [mm] (OCC bounding boxes are padded)
nx = m * Ceil(L / (size * aspect) - 1e-9);
For j In {0:2}
  For k In {0:2}
    Transfinite Curve{ Curve In BoundingBox{-e, ys[j] - e, zs[k] - e, L + e, ys[j] + e, zs[k] + e} } = nx + 1;
  EndFor
EndFor
xs[] = {0, L};
For i In {0:1}
  x = xs[i];
  For j In {0:1}
    ny = m * Ceil((ys[j + 1] - ys[j]) / size - 1e-9);
    For k In {0:2}
      Transfinite Curve{ Curve In BoundingBox{x - e, ys[j] - e, zs[k] - e, x + e, ys[j + 1] + e, zs[k] + e} } = ny + 1;
    EndFor
  EndFor
  For k In {0:1}
    nz = m * Ceil((zs[k + 1] - zs[k]) / size - 1e-9);
    For j In {0:2}
      Transfinite Curve{ Curve In BoundingBox{x - e, ys[j] - e, zs[k] - e, x + e, ys[j] + e, zs[k + 1] + e} } = nz + 1;
    EndFor
  EndFor
EndFor
Transfinite Surface{:};
Recombine Surface{:};
Transfinite Volume{:};
Recombine Volume{:};

coil[] = Volume In BoundingBox{-e, ys[1] - e, zs[1] - e, L + e, ys[2] + e, zs[2] + e};
lce[] = Volume In BoundingBox{-e, -e, -e, L + e, ys[1] + e, zs[2] + e};
lce[] += Volume In BoundingBox{-e, ys[1] - e, -e, L + e, ys[2] + e, zs[1] + e};
Physical Volume("lce", 1) = lce[];
Physical Volume("coil", 2) = coil[];

Physical Surface("clamp", 1) = Surface In BoundingBox{-e, -e, -e, e, W / 2 + e, H / 2 + e};
Physical Surface("end", 2) = Surface In BoundingBox{L - e, -e, -e, L + e, W / 2 + e, H / 2 + e};
sides[] = Surface In BoundingBox{-e, -e, -e, L + e, e, H / 2 + e};
sides[] += Surface In BoundingBox{-e, -e, -e, L + e, W / 2 + e, e};
Physical Surface("sides", 3) = sides[];
Physical Surface("sym_y", 4) = Surface In BoundingBox{-e, W / 2 - e, -e, L + e, W / 2 + e, H / 2 + e};
Physical Surface("sym_z", 5) = Surface In BoundingBox{-e, -e, H / 2 - e, L + e, W / 2 + e, H / 2 + e};
