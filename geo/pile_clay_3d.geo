// The tutorial's pile in clay (docs/tutorial/pile_clay.json, pile.geo with
// L = 6) in full 3D for the CalculiX peer (crates/bench/src/plastic_peer.rs):
// the half model y >= 0 (x = r cos(theta), y = r sin(theta), z up; metres),
// a structured mesh of 20-node hexahedra (C3D20R in the deck).
//
// Plan view (z = const): the pile's half disc r <= a is an O-grid (a core
// rectangle [-c, c] x [0, c] and three ring blocks over theta 0-45, 45-135,
// 135-180 deg); the soil ring a <= r <= R continues the same three blocks
// outward, its radial cells growing by `q` from about `h` at r = a.
// Elevation: the plan is extruded from z = 0 down to the pile toe z = -L in
// layers of about `h * hz`, then down to the base z = -H in layers growing
// by `q` from that size.
//
//   z =   0  +-----+-------------------------------+   pile head | soil top
//            |pile |            soil               |
//   z =  -6  +-----+                               |   r = R = 12 (fixed)
//            |           soil                      |
//   z = -24  +-------------------------------------+   base (fixed)
//          r = 0  r = a = 0.6
//
// Parameters (gmsh -setnumber NAME VALUE):
//   h    element size at the pile: circumferential at r = a and vertical
//        along the pile [m]
//   q    growth of the element size away from the pile (radially below r = R,
//        vertically below the toe) [-]
//   hz   vertical layers along the pile are h * hz thick [-]
// Physical volumes "pile" and "soil"; the node sets (head, symmetry plane,
// outer side, base) are found from the coordinates by the peer.
If (!Exists(h)) h = 0.3; EndIf
If (!Exists(q)) q = 1.3; EndIf
If (!Exists(hz)) hz = 1.0; EndIf

a = 0.6;   // pile radius
L = 6;     // pile length
R = 12;    // soil radius
H = 24;    // soil depth
c = a / 2; // half width of the pile's core rectangle

nq = Ceil(Pi * a / (4 * h)); // cells per 45 deg of arc
If (nq < 2) nq = 2; EndIf
m = nq;                       // radial cells of the pile's ring blocks
// Radial cells of the soil: first cell ~h at r = a, ratio q, out to R.
nr = Ceil(Log(1 + (R - a) * (q - 1) / h) / Log(q));
If (nr < 4) nr = 4; EndIf

s = Sqrt(0.5);
Point(1) = {0, 0, 0};
Point(2) = {c, 0, 0};
Point(3) = {c, c, 0};
Point(4) = {-c, c, 0};
Point(5) = {-c, 0, 0};
Point(6) = {a, 0, 0};
Point(7) = {a * s, a * s, 0};
Point(8) = {-a * s, a * s, 0};
Point(9) = {-a, 0, 0};
Point(10) = {R, 0, 0};
Point(11) = {R * s, R * s, 0};
Point(12) = {-R * s, R * s, 0};
Point(13) = {-R, 0, 0};

// core
Line(1) = {5, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 5};
// pile ring: spokes from the core outward, arcs at r = a
Line(5) = {2, 6};
Line(6) = {3, 7};
Line(7) = {4, 8};
Line(8) = {5, 9};
Circle(9) = {6, 1, 7};
Circle(10) = {7, 1, 8};
Circle(11) = {8, 1, 9};
// soil ring: spokes from r = a outward, arcs at r = R
Line(12) = {6, 10};
Line(13) = {7, 11};
Line(14) = {8, 12};
Line(15) = {9, 13};
Circle(16) = {10, 1, 11};
Circle(17) = {11, 1, 12};
Circle(18) = {12, 1, 13};

Transfinite Curve {1, 3, 10, 17} = 2 * nq + 1;
Transfinite Curve {2, 4, 9, 11, 16, 18} = nq + 1;
Transfinite Curve {5, 6, 7, 8} = m + 1;
Transfinite Curve {12, 13, 14, 15} = nr + 1 Using Progression q;

Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Curve Loop(2) = {5, 9, -6, -2};
Plane Surface(2) = {2};
Curve Loop(3) = {6, 10, -7, -3};
Plane Surface(3) = {3};
Curve Loop(4) = {7, 11, -8, -4};
Plane Surface(4) = {4};
Curve Loop(5) = {12, 16, -13, -9};
Plane Surface(5) = {5};
Curve Loop(6) = {13, 17, -14, -10};
Plane Surface(6) = {6};
Curve Loop(7) = {14, 18, -15, -11};
Plane Surface(7) = {7};
Transfinite Surface {1} = {5, 2, 3, 4};
Transfinite Surface {2} = {2, 6, 7, 3};
Transfinite Surface {3} = {3, 7, 8, 4};
Transfinite Surface {4} = {4, 8, 9, 5};
Transfinite Surface {5} = {6, 10, 11, 7};
Transfinite Surface {6} = {7, 11, 12, 8};
Transfinite Surface {7} = {8, 12, 13, 9};
Recombine Surface {1:7};

// Layers along the pile: uniform, about h * hz thick.
nz = Ceil(L / (h * hz));
// Layers below the toe: the first h * hz thick, growing by q (the last
// layer takes the rest).
d0 = L / nz;
n2 = Ceil(Log(1 + (H - L) * (q - 1) / d0) / Log(q));
If (n2 < 2) n2 = 2; EndIf
For k In {1 : n2}
  one2[k - 1] = 1;
  frac2[k - 1] = d0 * (q^k - 1) / (q - 1) / (H - L);
EndFor
frac2[n2 - 1] = 1;

pile[] = {};
soil[] = {};
For i In {1 : 7}
  top[] = Extrude {0, 0, -L} { Surface{i}; Layers{nz}; Recombine; };
  If (i <= 4)
    pile[] += top[1];
  Else
    soil[] += top[1];
  EndIf
  low[] = Extrude {0, 0, -(H - L)} { Surface{top[0]}; Layers{one2[], frac2[]}; Recombine; };
  soil[] += low[1];
EndFor

Physical Volume("pile") = {pile[]};
Physical Volume("soil") = {soil[]};

// 20-node hexahedra (serendipity), mid-edge nodes on the arcs.
Mesh.ElementOrder = 2;
Mesh.SecondOrderIncomplete = 1;
Mesh.SecondOrderLinear = 0;
