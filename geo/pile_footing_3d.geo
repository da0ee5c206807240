// Scene P in full 3D (the CalculiX peer of geo/pile_footing.geo): the
// meridional section revolved by pi about the z axis, giving the half model
// y >= 0 (x = r cos(theta), y = r sin(theta), z axial; metres).
//
// The section (x = r, z) is split at z = 0.25 and z = 0.75 across the pile
// and the footing, so the symmetry plane y = 0 carries mesh lines on the cuts
// b-b (z = 0.25) and a-a (z = 0.75) for x in [-3, 3]: nodal stresses are read
// there directly. Pile and footing share one conforming mesh; the peer
// (crates/bench/src/peer3d.rs) duplicates the nodes of the pile side
// r = 0.5, 0 <= z < 1 itself to make the joint.
//
//   z = 2.0  +-----+------------------------+
//            |     |        footing         |
//   z = 1.0  +-----+------------------------+   (head r <= 0.5 bonded)
//            |     |                        |
//   z = 0.75 +-----+------------------------+   cut a-a
//            |pile |                        |
//   z = 0.25 +-----+------------------------+   cut b-b
//            |     |                        |
//   z = 0.0  |     +------------------------+ r = 3.0
//            |     |
//   z =-1.5  +-----+  pile end (loaded)
//          r = 0  r = 0.5
//
// Parameters (gmsh -setnumber NAME VALUE):
//   size   element size at the pile side r = 0.5, 0 <= z <= 1 [m]
//   growth size far from the pile side = growth * size (capped at sizemax)
//   sizemax largest element size [m]
//   order  1 = linear, 2 = quadratic tetrahedra
SetFactory("OpenCASCADE");
If (!Exists(size)) size = 0.1; EndIf
If (!Exists(growth)) growth = 4; EndIf
If (!Exists(sizemax)) sizemax = 0.6; EndIf
If (!Exists(order)) order = 2; EndIf

a = 0.5;
zend = -1.5;
zhead = 1.0;
rf = 3.0;
hf = 2.0;
zb = 0.25;
za = 0.75;

// Section rectangles in the plane (x, gmsh-y), rotated into (x, z) below.
Rectangle(1) = {0, zend, 0, a, -zend};        // pile below the footing
Rectangle(2) = {0, 0, 0, a, zb};              // pile, 0 .. 0.25
Rectangle(3) = {0, zb, 0, a, za - zb};        // pile, 0.25 .. 0.75
Rectangle(4) = {0, za, 0, a, zhead - za};     // pile, 0.75 .. 1
Rectangle(5) = {0, zhead, 0, a, hf - zhead};  // footing above the pile head
Rectangle(6) = {a, 0, 0, rf - a, zb};         // footing, 0 .. 0.25
Rectangle(7) = {a, zb, 0, rf - a, za - zb};   // footing, 0.25 .. 0.75
Rectangle(8) = {a, za, 0, rf - a, zhead - za};// footing, 0.75 .. 1
Rectangle(9) = {a, zhead, 0, rf - a, hf - zhead}; // footing, 1 .. 2
Rotate {{1, 0, 0}, {0, 0, 0}, Pi / 2} { Surface{1:9}; }
Coherence;

// Revolve by pi about the z axis into y >= 0.
Extrude {{0, 0, 1}, {0, 0, 0}, Pi} { Surface{:}; }
Coherence;

e = 1e-6;
pile() = Volume In BoundingBox {-a - e, -e, zend - e, a + e, a + e, zhead + e};
all() = Volume{:};
footing() = all();
footing() -= pile();
Physical Volume("pile") = {pile()};
Physical Volume("footing") = {footing()};

// Size: `size` within 0.05 of the pile side, growing linearly with the
// distance d to it (in the meridional plane) to growth * size at d = 1,
// never above sizemax. (One MathEval field: in gmsh 4.8 a MathEval that
// refers to another field hangs.)
Field[1] = MathEval;
Field[1].F = Sprintf("min(%g, %g * (1 + (%g - 1) * min(1, max(0, (sqrt((sqrt(x*x + y*y) - 0.5)^2 + max(0, max(-z, z - 1))^2) - 0.05) / 0.95))))", sizemax, size, growth);
Background Field = 1;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;
Mesh.ElementOrder = order;
Mesh.SecondOrderLinear = 0;
Mesh.Optimize = 1;
