#version 450 core
// One triangle covering the whole viewport, from gl_VertexID alone (draw 3 vertices, no
// attributes; an empty VAO must still be bound in a core context).

void main()
{
    const vec2 corner = vec2((gl_VertexID << 1) & 2, gl_VertexID & 2); // (0,0) (2,0) (0,2)
    gl_Position = vec4(corner * 2.0 - 1.0, 0.0, 1.0);
}
