#version 450 core
// Passes the surface's triangles (skirts dropped, as the CPU drops every triangle with a skirt
// vertex; walls, which have no area seen from above, too) with all three corners to the
// fragment stage, which interpolates the height at the sample itself and decides coverage with
// the CPU's tolerance; the rasterizer only finds candidate texels. Samples lie exactly on
// triangle edges, where the top-left rule would leave the surface's outer border out, so the
// triangle is grown about its incentre until every edge has moved out by `u_grow` texels (more
// than the rasterizer's subpixel snapping).
layout(triangles) in;
layout(triangle_strip, max_vertices = 3) out;

in vec3 g_texel[];
flat in int g_skirt[];

uniform vec2 u_texels; // the window texture's size
uniform float u_grow;

flat out vec3 f_corner[3];

void main() {
    if (g_skirt[0] != 0 || g_skirt[1] != 0 || g_skirt[2] != 0)
        return;
    vec2 a = g_texel[0].xy, b = g_texel[1].xy, c = g_texel[2].xy;
    float twice_area = abs((b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y));
    if (twice_area < 1e-12)
        return;
    float la = distance(b, c), lb = distance(c, a), lc = distance(a, b);
    float perimeter = la + lb + lc;
    vec2 incentre = (la * a + lb * b + lc * c) / perimeter;
    float inradius = twice_area / perimeter;
    float scale = 1.0 + u_grow / inradius;
    for (int k = 0; k < 3; ++k) {
        f_corner[0] = g_texel[0];
        f_corner[1] = g_texel[1];
        f_corner[2] = g_texel[2];
        vec2 p = incentre + (g_texel[k].xy - incentre) * scale;
        gl_Position = vec4(p / u_texels * 2.0 - 1.0, 0.0, 1.0);
        EmitVertex();
    }
    EndPrimitive();
}
