// chessboard.pov: scenes/bench/chessboard.yml in POV-Ray 3.7's language, for `rayforge bench
// scenes` (see that file for why the board is not Fundamentals of Ray Tracing's own scene).
// Render: povray +Ichessboard.pov +W1920 +H1080 -A +FN File_Gamma=1.0
//
// Matching rayforge, as in cover.pov: transforms carry over unchanged (same handedness, same
// order, radians to degrees); `angle` is the YAML field of view across the wider side, widened
// as the book's view transform widens it when `up` is not perpendicular to the line of sight
// (|left| = 0.87416 here: 2·atan(tan(0.45) / 0.87416) = 57.850°); `phong`/`phong_size` are the
// book's specular/shininess; ambient_light is the lights' summed intensity (the book counts the
// ambient term once per light); a pattern written inside the object before its transforms
// moves with it, as the book's patterns live in object space. The glass: `transmit` and `ior`,
// its diffuse divided by (1 − transmit) (0.1 / 0.1 = 1) because POV-Ray dims a transparent
// surface's own light by that factor and the book does not,
// with `fresnel on` where the book mixes by Schlick's approximation, and POV-Ray lets light
// through the balls into their shadows where the book's are opaque. max_trace_level 6 is
// rayforge's depth 5 (POV-Ray counts the camera ray as level 1); POV-Ray keeps its adaptive
// depth control (adc_bailout), as a user would.
#version 3.7;

global_settings { assumed_gamma 1.0 max_trace_level 6 ambient_light rgb <1.2, 1.1, 1.7> }

camera {
  perspective
  location <0, 5, -9>
  look_at <0, 0, 0>
  sky <0, 1, 0>
  right x * 1920 / 1080
  up y
  angle 57.850
}

light_source { <-45, 25, -50> color rgb <0.4, 0.4, 0.1> }
light_source { <5, 90, -40> color rgb <0.5, 0.5, 1.5> }
light_source { <-25, 30, -40> color rgb <0.3, 0.2, 0.1> }

// the table under the board
plane {
  y, -0.5
  pigment { color rgb <0.5, 0.3, 0.1> }
  finish { ambient 0.1 diffuse 0.7 reflection { 0.1 } }
}

// the board
box {
  -1, 1
  pigment {
    checker color rgb <0.30, 0.30, 0.40>, color rgb <0.75, 0.70, 0.10>
    scale 0.25
    translate <0, 0.1, 0>
  }
  finish { ambient 0.1 diffuse 0.8 phong 0.3 phong_size 50 reflection { 0.15 } }
  scale <4, 0.25, 4>
  translate <0, -0.25, 0>
}

#declare Glass = material {
  texture {
    pigment { color rgbt <0.05, 0.08, 0.1, 0.9> }
    finish { ambient 0 diffuse 1 phong 1 phong_size 300 reflection { 0.9 fresnel on } }
  }
  interior { ior 1.55 }
}

sphere { 0, 1 material { Glass } scale 0.72 translate <-1.8, 0.72, 0> }
sphere { 0, 1 material { Glass } scale 0.72 translate <0, 0.72, 0> }
sphere { 0, 1 material { Glass } scale 0.72 translate <1.8, 0.72, 0> }
