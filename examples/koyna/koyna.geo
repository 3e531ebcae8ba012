// Koyna-like gravity dam on a rock foundation, for pfeie (2D, plane strain).
// Geometry after Chopra & Chakrabarti (1973): height 103 m, base 70 m, crest 14.8 m,
// vertical upstream face, downstream slope up to the neck at 66.5 m.
// Physical groups: blocks "rock", "dam_lower", "dam_upper"; interfaces "dam_rock"
// (the dam-foundation joint) and "neck" (a lift joint at the slope change);
// faces "upstream_lower", "upstream_upper", "reservoir_floor", "rock_bottom".
// Regenerate the mesh with:  gmsh koyna.geo -2 -format msh41 -o koyna.msh

h_dam = 4.0;     // element size in the dam (m)
h_rock = 10.0;   // element size at the far rock boundaries (m)
L_up = 70.0;     // rock extent upstream of the heel (m)
L_dn = 70.0;     // rock extent downstream of the toe (m)
D = 70.0;        // rock depth (m)

// dam
Point(1) = {0, 0, 0, h_dam};
Point(2) = {70, 0, 0, h_dam};
Point(3) = {14.8, 66.5, 0, h_dam};
Point(4) = {14.8, 103, 0, h_dam};
Point(5) = {0, 103, 0, h_dam};
Point(6) = {0, 66.5, 0, h_dam};
// rock
Point(7) = {-L_up, 0, 0, h_rock};
Point(8) = {-L_up, -D, 0, h_rock};
Point(9) = {70 + L_dn, -D, 0, h_rock};
Point(10) = {70 + L_dn, 0, 0, h_rock};

Line(1) = {1, 2};      // dam-rock joint
Line(2) = {2, 3};      // downstream face, lower
Line(3) = {3, 6};      // neck (lift joint)
Line(4) = {6, 1};      // upstream face, lower
Line(5) = {3, 4};      // downstream face, upper
Line(6) = {4, 5};      // crest
Line(7) = {5, 6};      // upstream face, upper
Line(8) = {7, 1};      // reservoir floor
Line(9) = {7, 8};
Line(10) = {8, 9};     // rock bottom
Line(11) = {9, 10};
Line(12) = {10, 2};

Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Curve Loop(2) = {-3, 5, 6, 7};
Plane Surface(2) = {2};
Curve Loop(3) = {8, 1, -12, -11, -10, -9};
Plane Surface(3) = {3};

Physical Surface("dam_lower") = {1};
Physical Surface("dam_upper") = {2};
Physical Surface("rock") = {3};
Physical Curve("dam_rock") = {1};
Physical Curve("neck") = {3};
Physical Curve("upstream_lower") = {4};
Physical Curve("upstream_upper") = {7};
Physical Curve("reservoir_floor") = {8};
Physical Curve("rock_bottom") = {10};

// Quadratic serendipity quadrilaterals only (Q8, no T6): the frontal-Delaunay for quads
// algorithm and the blossom full-quad recombination, which meshes at twice the size and
// splits every cell into quadrilaterals, so the element sizes above hold. gmsh 4.15 warns
// "Cannot apply Blossom: odd number of triangles" for dam_lower and recombines that
// surface with its simple full-quad algorithm: 583 Q8 cells, 1,876 nodes.
Mesh.ElementOrder = 2;
Mesh.SecondOrderIncomplete = 1;
Mesh.RecombineAll = 1;
Mesh.Algorithm = 8;
Mesh.RecombinationAlgorithm = 3;
