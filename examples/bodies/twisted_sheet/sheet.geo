// A thin LCE sheet, 20 mm x 4 mm x 0.5 mm, whose director turns through the thickness (a twisted
// nematic sheet). Structured hexahedra; [mesh] size_factor s multiplies the divisions by 1/s.
// Cells "sheet"; facets "bottom" (z = 0), "top" (z = 0.5). Units: mm.
SetFactory("OpenCASCADE");
L = 20; W = 4; H = 0.5;
m = Round(1 / Mesh.MeshSizeFactor);
Box(1) = {0, 0, 0, L, W, H};
e = 1e-4;
Transfinite Curve{ Curve In BoundingBox{-e, -e, -e, L + e, W + e, H + e} } = 2 * m + 1;  // through the thickness
For y In {0:1}
  For z In {0:1}
    Transfinite Curve{ Curve In BoundingBox{-e, y * W - e, z * H - e, L + e, y * W + e, z * H + e} } = 20 * m + 1;
  EndFor
EndFor
For x In {0:1}
  For z In {0:1}
    Transfinite Curve{ Curve In BoundingBox{x * L - e, -e, z * H - e, x * L + e, W + e, z * H + e} } = 4 * m + 1;
  EndFor
EndFor
Transfinite Surface{:};
Recombine Surface{:};
Transfinite Volume{:};
Recombine Volume{:};
Physical Volume("sheet", 1) = {1};
Physical Surface("bottom", 1) = Surface In BoundingBox{-e, -e, -e, L + e, W + e, e};
Physical Surface("top", 2) = Surface In BoundingBox{-e, -e, H - e, L + e, W + e, H + e};
