// bench/povray/whitted.glint in POV-Ray 3.7: the same objects, materials, lights and
// camera (see camera.inc for how the camera is matched).
#version 3.7;
#include "camera.inc"
GlintCamera(<0, 3.2, 10>, <0, 0.9, 0>, 40)

global_settings { assumed_gamma 1.0 ambient_light rgb 0.1 max_trace_level 5 }
background { rgb <0.05, 0.08, 0.22> }

light_source { <5, 9, 6> color rgb <0.85, 0.85, 0.8> }
light_source { <-6, 7, 4> color rgb <0.35, 0.38, 0.45> }

plane { y, 0
  texture { pigment { checker rgb 0.9, rgb 0.12 } finish { ambient 1 diffuse 1 } }
}
sphere { <-1.2, 1, -0.5>, 1
  texture { pigment { rgb 0.05 } finish { ambient 1 diffuse 1 phong 0.9 phong_size 200 reflection 0.85 } }
}
sphere { <1.1, 0.75, 1.6>, 0.75
  texture { pigment { rgbt <0, 0, 0, 0.9> } finish { ambient 0 diffuse 0 phong 1 phong_size 200 reflection 0.1 } }
  interior { ior 1.5 }
}
sphere { <-2.3, 0.5, 1.5>, 0.5
  texture { pigment { rgb <0.15, 0.25, 0.8> } finish { ambient 1 diffuse 1 specular 0.5 roughness 1/80 } }
}
cylinder { <0, -1, 0>, <0, 1, 0>, 1 scale <0.45, 1, 0.45> translate <-3.6, 1, -2>
  texture { pigment { rgb <0.15, 0.65, 0.2> } finish { ambient 1 diffuse 1 specular 0.3 roughness 1/20 } }
}
cone { <0, -1, 0>, 1, <0, 1, 0>, 0 scale <0.6, 0.9, 0.6> translate <3.4, 0.9, -1.4>
  texture { pigment { rgb <0.85, 0.7, 0.1> } finish { ambient 1 diffuse 1 phong 0.5 phong_size 60 reflection 0.05 } }
}
box { -1, 1 scale 0.6 rotate <0, 30, 0> translate <1, 0.6, -2.8>
  texture { pigment { rgb <0.8, 0.12, 0.1> } finish { ambient 1 diffuse 1 specular 0.4 roughness 1/40 reflection 0.05 } }
}
