// Included by test/bad_include.frag. Deliberately broken: line 5 uses an undeclared name,
// which the test expects to be reported as test/broken.glsl:5.
vec4 brokenColour()
{
    return vec4(undeclared_name_on_line_5);
}
