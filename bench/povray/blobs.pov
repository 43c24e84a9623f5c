// The blobs of scenes/blobs.glint (without the floor) as a coverage mask. POV-Ray's
// blob field is strength·(1 − (r/radius)²)², the same as glint's; `sturm` asks for its
// most accurate root solver.
#version 3.7;
#include "camera.inc"
GlintCamera(<0, 3, 9>, <0, 1, 0>, 36)

blob {
  threshold 0.5
  sphere { <0, 0, 0>, 1.1, 1 }
  sphere { <0.75, 0.3, 0>, 0.8, 1 }
  sphere { <-0.6, 0.5, 0.3>, 0.8, 1 }
  sphere { <0, -0.2, 0.7>, 0.7, 1 }
  sphere { <0.3, 0.75, 0.75>, 0.7, -1.5 }
  sturm
  translate <-2.6, 0.95, 0>
  texture { Flat }
}

blob {
  threshold 0.4
  cylinder { <-0.9, 0, 0>, <0.9, 0, 0>, 0.55, 1 }
  sphere { <0, 0, 0>, 1, 1 scale <0.5, 1.3, 0.5> translate <0, 0.6, 0> }
  sphere { <-1.1, 0, 0>, 0.7, 0.9 }
  sphere { <1.1, 0, 0>, 0.7, 0.9 }
  sturm
  rotate <0, 25, 0>
  translate <0, 0.75, 0.6>
  texture { Flat }
}

blob {
  threshold 0.255
  sphere { <-0.8, 0, 0>, 1, 1 }
  sphere { <0.8, 0, 0>, 1, 1 }
  sturm
  scale 0.8
  translate <2.6, 0.6, 0>
  texture { Flat }
}
