// The solids of scenes/csg.glint (without the floor) as a coverage mask.
#version 3.7;
#include "camera.inc"
GlintCamera(<0, 3.4, 9.5>, <0, 0.8, 0>, 36)

// (cube ∩ ball) − (x, y and z cylinders)
difference {
  intersection {
    box { -1, 1 }
    sphere { 0, 1 scale 1.35 }
  }
  cylinder { <0, -1, 0>, <0, 1, 0>, 1 scale <0.55, 1.6, 0.55> }
  cylinder { <0, -1, 0>, <0, 1, 0>, 1 scale <0.55, 1.6, 0.55> rotate <90, 0, 0> }
  cylinder { <0, -1, 0>, <0, 1, 0>, 1 scale <0.55, 1.6, 0.55> rotate <0, 0, 90> }
  scale 0.85
  rotate <0, 30, 0>
  translate <-2.7, 0.85, 0>
  texture { Flat }
}

// The lens.
intersection {
  sphere { 0, 1 scale 1.6 translate <0, 0, -1.25> }
  sphere { 0, 1 scale 1.6 translate <0, 0, 1.25> }
  rotate <0, -20, 0>
  translate <0, 1.25, 1.2>
  texture { Flat }
}

// The bowl: a plane is the half-space below it inside CSG, in both renderers.
intersection {
  difference {
    sphere { 0, 1 }
    sphere { 0, 1 scale 0.88 }
  }
  plane { y, 0 translate <0, 0.35, 0> }
  translate <2.6, 0.92, 0.4>
  texture { Flat }
}

// The hyperboloid tower closed by its box, and the torus collar.
intersection {
  quadric { <1, -0.25, 1>, <0, 0, 0>, <0, 0, 0>, -0.16 }
  box { <-1, -1.4, -1>, <1, 1.4, 1> }
  translate <0.9, 1.4, -3>
  texture { Flat }
}
torus { 1, 0.3 scale 0.75 translate <0.9, 1.4, -3> texture { Flat } }
