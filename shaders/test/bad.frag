#version 450 core
// Deliberately broken: line 7 has a syntax error (an operator without its right operand)
// that the test expects to be reported as test/bad.frag:7.
layout(location = 0) out vec4 colour;
void main()
{
    colour = vec4(1.0) * ;
}
