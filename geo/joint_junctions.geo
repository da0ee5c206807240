// Joint ends, for the mesh tests: three bodies and three joints.
//
//   z = 2  +-----------------------+
//          |   C     crack (inside C, tips at r = 0.5 and 1.5)
//          |     o=============o   |   z = 1.5
//   z = 1  +===========+===========+   "top": C over A and B, from the axis
//          |    A      I     B     |   "ab": between A and B, r = 1
//   z = 0  +-----------+-----------+
//        r = 0        r = 1       r = 2
If (!Exists(size)) size = 0.2; EndIf
If (!Exists(order)) order = 2; EndIf
If (!Exists(quads)) quads = 0; EndIf
Point(1) = {0, 0, 0, size};   Point(2) = {1, 0, 0, size};   Point(3) = {2, 0, 0, size};
Point(4) = {0, 1, 0, size};   Point(5) = {1, 1, 0, size};   Point(6) = {2, 1, 0, size};
Point(7) = {0, 2, 0, size};   Point(8) = {2, 2, 0, size};
Point(9) = {0.5, 1.5, 0, size};  Point(10) = {1.5, 1.5, 0, size};
Line(1) = {1, 2};  Line(2) = {2, 3};  Line(3) = {3, 6};  Line(4) = {6, 5};
Line(5) = {5, 4};  Line(6) = {4, 1};  Line(7) = {2, 5};  Line(8) = {6, 8};
Line(9) = {8, 7};  Line(10) = {7, 4}; Line(11) = {9, 10};
Curve Loop(1) = {1, 7, 5, 6};        Plane Surface(1) = {1};   // A
Curve Loop(2) = {2, 3, 4, -7};       Plane Surface(2) = {2};   // B
Curve Loop(3) = {-5, -4, 8, 9, 10};  Plane Surface(3) = {3};   // C
Curve{11} In Surface{3};
Mesh.ElementOrder = order;
Mesh.RecombineAll = quads;
Physical Surface("A") = {1};
Physical Surface("B") = {2};
Physical Surface("C") = {3};
Physical Curve("ab") = {7};
Physical Curve("top") = {4, 5};
Physical Curve("crack") = {11};
Physical Curve("axis") = {6, 10};
Physical Curve("bottom") = {1, 2};
