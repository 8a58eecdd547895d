#version 450 core
// Transform feedback check: captures twice the vertex index (no rasterisation needed).
out float doubled_id;

void main()
{
    doubled_id = 2.0 * float(gl_VertexID);
    gl_Position = vec4(0.0);
}
