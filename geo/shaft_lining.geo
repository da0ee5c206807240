// Shaft lining in soil: a concrete ring (ri..ro) from the surface to depth
// D, soil outside it and below the shaft's floor. Meridional half plane
// r >= 0: gmsh x = r, gmsh y = z (metres).
//
//   z =  0       +--+------------------------------+   lining_top | soil_top
//          void  |  | lining_out (joint, r = ro)    |
//   z = -D  +----+--+ (lining base bonded)          |   soil_outer (r = R)
//           |  shaft_floor                         |
//           |                soil                  |
//   z = -H  +--------------------------------------+   soil_bottom
//         r = 0  ri ro                           r = R
//
// Parameters (axijoint --set NAME=VALUE):
//   size     element size along the lining [m]
//   coarsen  far-field element size / size
//   ri, ro   inner and outer radius of the lining [m]
//   D        depth of the shaft [m]
//   R, H     radius and depth of the soil [m]
If (!Exists(size)) size = 0.5; EndIf
If (!Exists(coarsen)) coarsen = 8; EndIf
If (!Exists(ri)) ri = 4.0; EndIf
If (!Exists(ro)) ro = 4.5; EndIf
If (!Exists(D)) D = 20.0; EndIf
If (!Exists(R)) R = 50.0; EndIf
If (!Exists(H)) H = 50.0; EndIf
far = coarsen * size;

Point(1) = {ri, 0, 0, size};
Point(2) = {ro, 0, 0, size};
Point(3) = {ro, -D, 0, size};
Point(4) = {ri, -D, 0, size};
Point(5) = {R, 0, 0, far};
Point(6) = {R, -H, 0, far};
Point(7) = {0, -H, 0, far};
Point(8) = {0, -D, 0, size};

Line(1) = {3, 2};  // lining_out (joint)
Line(2) = {2, 1};  // lining_top
Line(3) = {1, 4};  // lining_in
Line(4) = {4, 3};  // lining base, bonded to the soil
Line(5) = {2, 5};  // soil_top
Line(6) = {5, 6};  // soil_outer
Line(7) = {6, 7};  // soil_bottom
Line(8) = {7, 8};  // axis
Line(9) = {8, 4};  // shaft_floor

Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Curve Loop(2) = {1, 5, 6, 7, 8, 9, 4};
Plane Surface(2) = {2};

Mesh.ElementOrder = 2;
Mesh.SecondOrderIncomplete = 0;
Mesh.RecombineAll = 1;

Physical Surface("lining") = {1};
Physical Surface("soil") = {2};
Physical Curve("lining_out") = {1};
Physical Curve("lining_top") = {2};
Physical Curve("lining_in") = {3};
Physical Curve("soil_top") = {5};
Physical Curve("soil_outer") = {6};
Physical Curve("soil_bottom") = {7};
Physical Curve("axis") = {8};
Physical Curve("shaft_floor") = {9};
