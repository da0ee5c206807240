// block_on_base.geo with a switch for the 8-node serendipity quadrilateral
// (Q8), for the element-family cases of the stability map
// (crates/solver/tests/stability.rs, docs/stability.md). Geometry, physical
// names and refinement are those of block_on_base.geo (included).
//
// Parameters (gmsh -setnumber NAME VALUE): a, size, refine, order, quads as
// in block_on_base.geo; serendipity 1 = Q8 instead of Q9 (order 2, quads 1).
If (!Exists(a)) a = 0.5; EndIf
If (!Exists(size)) size = 0.25; EndIf
If (!Exists(refine)) refine = 4; EndIf
If (!Exists(order)) order = 2; EndIf
If (!Exists(quads)) quads = 1; EndIf
If (!Exists(serendipity)) serendipity = 0; EndIf
Include "block_on_base.geo";
Mesh.SecondOrderIncomplete = serendipity;
