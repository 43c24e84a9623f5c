// The implicit surfaces and superellipsoids of scenes/implicit.glint (without the
// floor) as a coverage mask. POV-Ray's isosurface is also the region f < 0 closed by
// its container; max_gradient is its Lipschitz bound, set above each function's real
// maximum slope so that its solver misses nothing.
#version 3.7;
#include "camera.inc"
GlintCamera(<0, 4.2, 10>, <0, 1.5, -1>, 40)

isosurface {
  function { pow(x, 4) - 5 * x * x + pow(y, 4) - 5 * y * y + pow(z, 4) - 5 * z * z + 11.8 }
  contained_by { box { -2.6, 2.6 } }
  max_gradient 80
  accuracy 0.00001
  scale 0.4
  rotate <0, 30, 0>
  translate <-2.7, 1.05, 0>
  texture { Flat }
}

isosurface {
  function { pow(x * x + 2.25 * z * z + y * y - 1, 3) - x * x * pow(y, 3) - 0.1125 * z * z * pow(y, 3) }
  contained_by { box { -1.4, 1.4 } }
  max_gradient 1200
  accuracy 0.00001
  scale 1.1
  translate <0, 1.15, 0.6>
  texture { Flat }
}

isosurface {
  function {
    max(abs(sin(4 * x) * cos(4 * y) + sin(4 * y) * cos(4 * z) + sin(4 * z) * cos(4 * x)) - 0.4,
        x * x + y * y + z * z - 1)
  }
  contained_by { box { -1.05, 1.05 } }
  max_gradient 14
  accuracy 0.00001
  translate <2.7, 1, 0>
  texture { Flat }
}

// POV-Ray's superellipsoid { <e, n> } has its pole on z: <e2, e1> turned onto y.
superellipsoid { <0.25, 0.25> rotate <-90, 0, 0> scale 0.8 rotate <0, 20, 0> translate <-2.4, 3, -3> texture { Flat } }
superellipsoid { <1, 0.3> rotate <-90, 0, 0> scale <1, 0.55, 1> rotate <20, 0, 0> translate <0, 3.5, -3> texture { Flat } }
superellipsoid { <3, 3> rotate <-90, 0, 0> scale 1.1 rotate <0, 30, 0> translate <2.4, 3, -3> texture { Flat } }
