#version 450 core
// One vertex per tessellation block or skirt segment; everything else comes from the
// instance buffer, indexed by the instance (one instance per selected patch).
out flat int v_primitive;
out flat int v_instance;

uniform int u_instance_offset; // first instance of this draw (GL 4.5 has no gl_BaseInstance)

void main() {
    v_primitive = gl_VertexID;
    v_instance = gl_InstanceID + u_instance_offset;
    gl_Position = vec4(0.0);
}
