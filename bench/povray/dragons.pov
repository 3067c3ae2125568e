// dragons.pov: the banner of The Ray Tracer Challenge's bonus chapter "Bounding boxes and
// hierarchies" (shared/models/bounding-boxes.yml, by Jamis Buck) in POV-Ray 3.7's language, for
// `rayforge bench scenes`: six Stanford dragons on pedestals, five in see-through boxes.
// The dragon itself comes from "dragon.inc", which `rayforge bench` writes from dragon.obj with
// rayforge's own OBJ reader (the same vertices, normals and triangles; the model is not in the
// repository, so neither is the include). Render, beside that include:
//   povray +Idragons.pov +W1920 +H1080 -A +FN File_Gamma=1.0
//
// Matching rayforge, as in cover.pov: transforms carry over unchanged (same handedness, same
// order; a group's transform follows its children's; radians become degrees); `angle` is the
// scene's 1.2 rad across the wider side, widened as the book's view transform widens it when
// `up` is not perpendicular to the line of sight (|left| = 0.98894: 69.350°) and kept when
// --width/--height change the aspect ratio, as rayforge keeps it; `phong`/`phong_size` are the
// book's specular/shininess; ambient_light is the lights' summed intensity, 1.5 (the book
// counts the ambient term once per light); `shadow: false` is `no_shadow`; the boxes'
// transparency is `transmit` with ior 1, and their diffuse is divided by (1 − transmit) because
// POV-Ray dims a transparent surface's own light by that factor and the book does not (so
// Bbox(0.4, 0.6) has diffuse 1, as do the others). max_trace_level 6 is rayforge's depth 5 (POV-Ray
// counts the camera ray as level 1). POV-Ray meshes are bounded by their own tree, as
// rayforge's are.
#version 3.7;

global_settings { assumed_gamma 1.0 max_trace_level 6 ambient_light rgb 1.5 }

#include "dragon.inc"

camera {
  perspective
  location <0, 2.5, -10>
  look_at <0, 1, 0>
  sky <0, 1, 0>
  right x * image_width / image_height
  up y
  angle 69.350
}

light_source { <-10, 100, -100> color rgb 1 }
light_source { <0, 100, 0> color rgb 0.1 }
light_source { <100, 10, -25> color rgb 0.2 }
light_source { <-100, 10, -25> color rgb 0.2 }

// The scene's defines.
#declare Pedestal = cylinder {
  <0, -0.15, 0>, <0, 0, 0>, 1
  pigment { color rgb 0.2 }
  finish { ambient 0 diffuse 0.8 reflection { 0.2 } }
}
#macro Placed() translate <0, 0.1217, 0> scale 0.268 #end
#macro Dragon_In(Colour)
  object {
    Dragon
    Placed()
    pigment { color rgb Colour }
    finish { ambient 0.1 diffuse 0.6 phong 0.3 phong_size 15 }
  }
#end
#macro Bbox(Diffuse, Transparency)
  box {
    -1, 1
    translate <1, 1, 1>
    scale <3.73335, 2.5845, 1.6283>
    translate <-3.9863, -0.1217, -1.1820>
    Placed()
    pigment { color rgbt <1, 1, 1, Transparency> }
    finish { ambient 0 diffuse Diffuse / (1 - Transparency) }
    interior { ior 1 }
    no_shadow
  }
#end

union {
  object { Pedestal }
  union { Dragon_In(<1, 0, 0.1>) Bbox(0.4, 0.6) }
  translate <0, 2, 0>
}

union {
  object { Pedestal }
  union { Dragon_In(<1, 0.5, 0.1>) Bbox(0.2, 0.8) rotate <0, 229.1831, 0> scale 0.75 }
  translate <2, 1, -1>
}

union {
  object { Pedestal }
  union { Dragon_In(<0.9, 0.5, 0.1>) Bbox(0.2, 0.8) rotate <0, -22.9183, 0> scale 0.75 }
  translate <-2, 0.75, -1>
}

union {
  object { Pedestal }
  union { Dragon_In(<1, 0.9, 0.1>) Bbox(0.1, 0.9) rotate <0, -11.4592, 0> scale 0.5 }
  translate <-4, 0, -2>
}

union {
  object { Pedestal }
  union { Dragon_In(<0.9, 1, 0.1>) Bbox(0.1, 0.9) rotate <0, 189.0761, 0> scale 0.5 }
  translate <4, 0, -2>
}

union {
  object { Pedestal }
  object { Dragon_In(<1, 1, 1>) rotate <0, 179.9947, 0> }
  translate <0, 0.5, -4>
}
