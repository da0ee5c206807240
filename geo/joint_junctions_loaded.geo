// joint_junctions.geo with its free faces named, so that a scene can load
// them: the stability map's case of two joints meeting at a corner and a
// joint touching the axis (crates/solver/tests/stability.rs,
// docs/stability.md). Geometry and the other physical names are those of
// joint_junctions.geo (included):
//
//   z = 2  +-----------------------+   c_top (loaded)
//          |   C     crack         |   c_side (r = 2, z = 1 .. 2)
//          |     o=============o   |
//   z = 1  +===========+===========+   "top" joint (from the axis)
//          |    A      I     B     |   b_side (r = 2, z = 0 .. 1)
//   z = 0  +-----------+-----------+   bottom (fixed)
//        r = 0        r = 1       r = 2
//
// Parameters (gmsh -setnumber NAME VALUE): size, order, quads.
If (!Exists(size)) size = 0.2; EndIf
If (!Exists(order)) order = 2; EndIf
If (!Exists(quads)) quads = 0; EndIf
Include "joint_junctions.geo";
Physical Curve("c_top") = {9};
Physical Curve("c_side") = {8};
Physical Curve("b_side") = {3};
