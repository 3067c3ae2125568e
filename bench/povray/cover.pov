// cover.pov: The Ray Tracer Challenge's cover (scenes/trtc/cover.yml) in POV-Ray 3.7's language,
// for `rayforge bench scenes`. Render: povray +Icover.pov +W1080 +H1080 -A +FN File_Gamma=1.0
//
// The same geometry, camera, lights and materials, term by term:
// - Both are left-handed with y up and apply transforms in the order written, and POV-Ray's
//   rotations turn the same way as the book's, so every transform carries over unchanged
//   (radians become degrees). The book's cube is box { -1, 1 }, its sphere sphere { 0, 1 }.
// - Camera: the book's field of view spans the wider side, POV-Ray's `angle` the width. The
//   book's view transform does not normalise its `left` vector, so an `up` that is not
//   perpendicular to the line of sight (this one is 30° off) shrinks the view by |left| =
//   0.86725 and widens the field: 2·atan(tan(0.785/2) / 0.86725) = 51.035°. `sky` is `up`.
// - Lighting: diffuse and `phong`/`phong_size` are the book's diffuse and specular/shininess
//   (both use the reflected light vector, in the light's colour). The book adds the ambient term
//   once per light, scaled by its intensity, so ambient_light is the lights' sum, 1.2.
// - Reflection: `reflection { r }` adds r × the reflected colour, as the book does.
// - The glass sphere: transparency 0.7 is `transmit 0.7` and `interior { ior 1.5 }`, and its
//   diffuse 0.2 becomes 0.2 / (1 − 0.7) = 0.667 because POV-Ray dims a transparent surface's own
//   light by (1 − transmit) and the book does not. The book
//   mixes reflection and refraction by Schlick's approximation when a surface has both, which
//   POV-Ray's `fresnel on` does with the exact Fresnel equations (a close match, not exact).
//   POV-Ray lets light through transparent objects into their shadows; the book's shadows are
//   opaque whatever casts them: the floor under the sphere is a little brighter in POV-Ray.
// - Depth: max_trace_level 6 is rayforge's depth 5 (POV-Ray counts the camera ray as level 1).
//   POV-Ray keeps its adaptive depth control (adc_bailout), the default a user gets.
// - assumed_gamma 1 (and File_Gamma=1.0 on the command line) keep colours linear, as rayforge
//   writes them.
#version 3.7;

global_settings { assumed_gamma 1.0 max_trace_level 6 ambient_light rgb 1.2 }

camera {
  perspective
  location <-6, 6, -10>
  look_at <6, 0, 6>
  sky <-0.45, 1, 0>
  right x
  up y
  angle 51.035
}

light_source { <50, 100, -50> color rgb 1 }
light_source { <-400, 50, -10> color rgb 0.2 }

#declare White = texture {
  pigment { color rgb 1 }
  finish { ambient 0.1 diffuse 0.7 reflection { 0.1 } }
}
#declare Blue = texture {
  pigment { color rgb <0.537, 0.831, 0.914> }
  finish { ambient 0.1 diffuse 0.7 reflection { 0.1 } }
}
#declare Red = texture {
  pigment { color rgb <0.941, 0.322, 0.388> }
  finish { ambient 0.1 diffuse 0.7 reflection { 0.1 } }
}
#declare Purple = texture {
  pigment { color rgb <0.373, 0.404, 0.550> }
  finish { ambient 0.1 diffuse 0.7 reflection { 0.1 } }
}

// The book's defines: standard-transform, then the size.
#macro Standard() translate <1, -1, 1> scale 0.5 #end
#macro Large() Standard() scale 3.5 #end
#macro Medium() Standard() scale 3 #end
#macro Small() Standard() scale 2 #end

// The white backdrop: rotate-x pi/2, then translate z 500.
plane {
  y, 0
  rotate <90, 0, 0>
  translate <0, 0, 500>
  pigment { color rgb 1 }
  finish { ambient 1 diffuse 0 }
}

// The glass sphere.
sphere {
  0, 1
  Large()
  pigment { color rgbt <0.373, 0.404, 0.550, 0.7> }
  finish { ambient 0 diffuse 0.667 phong 1 phong_size 200 reflection { 0.7 fresnel on } }
  interior { ior 1.5 }
}

box { -1, 1 Medium() translate <4, 0, 0>        texture { White } }
box { -1, 1 Large()  translate <8.5, 1.5, -0.5> texture { Blue } }
box { -1, 1 Large()  translate <0, 0, 4>        texture { Red } }
box { -1, 1 Small()  translate <4, 0, 4>        texture { White } }
box { -1, 1 Medium() translate <7.5, 0.5, 4>    texture { Purple } }
box { -1, 1 Medium() translate <-0.25, 0.25, 8> texture { White } }
box { -1, 1 Large()  translate <4, 1, 7.5>      texture { Blue } }
box { -1, 1 Medium() translate <10, 2, 7.5>     texture { Red } }
box { -1, 1 Small()  translate <8, 2, 12>       texture { White } }
box { -1, 1 Small()  translate <20, 1, 9>       texture { White } }
box { -1, 1 Large()  translate <-0.5, -5, 0.25> texture { Blue } }
box { -1, 1 Large()  translate <4, -4, 0>       texture { Red } }
box { -1, 1 Large()  translate <8.5, -4, 0>     texture { White } }
box { -1, 1 Large()  translate <0, -4, 4>       texture { White } }
box { -1, 1 Large()  translate <-0.5, -4.5, 8>  texture { Purple } }
box { -1, 1 Large()  translate <0, -8, 4>       texture { White } }
box { -1, 1 Large()  translate <-0.5, -8.5, 8>  texture { White } }
