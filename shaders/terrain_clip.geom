#version 450 core
// For patches partly outside the valid extent only (a second draw): clips each triangle
// exactly at the terrain's last finest column and row (cell.x <= valid_extent.x, cell.y <=
// valid_extent.y, in level cells: inside a cell when the level's samples miss the border, the
// surface there running towards the edge-extended sample beyond it) and hangs a wall under
// every cut, skirt_depth deep. The terrain then ends on its true border with a closed side,
// instead of fragments discarded over the padding with the skirts of inner seams showing.
// Cut points are computed from the edge's endpoints in a fixed order, so the two triangles
// sharing an edge produce the same point, bit for bit (`precise`): the clipped surface and
// its walls stay watertight.
#include "terrain_common.glsl"

// The valid extent at or beyond which an instance is not clipped on that side: C for patches
// (FrameUniforms), larger for a scheme whose pieces have more cells than a patch (clipmaps).
uniform float u_unclipped_extent;
// Per axis: the valid extent there is a grid line of every piece (clipmaps on the globe: a
// level cut to one turn, whose ends are one meridian drawn on both sides; a pole row), so a
// triangle beyond it is dropped whole, as west and north of valid_start, and nothing is cut
// or walled.
uniform bvec2 u_drop_beyond;

layout(triangles) in;
// A triangle clipped by two lines has at most 5 corners (3 triangles) and 2 cuts (2 quads).
layout(triangle_strip, max_vertices = 17) out;

precise gl_Position;

in Vertex {
    vec3 position;
    vec3 texcoord;
    vec2 cell;
    flat int level;
    flat int layer;     // texture-array slot of the drawn patch (heights, normals)
    flat float factor;
    flat int skirt;
} vin[];
in Capture {
    vec3 tf_position;
    flat int tf_instance;
    flat int tf_skirt;
} cin[];

out Vertex {
    vec3 position;
    vec3 texcoord;
    vec2 cell;
    flat int level;
    flat int layer;     // texture-array slot of the drawn patch (heights, normals)
    flat float factor;
    flat int skirt;
} vout;
out Capture {
    vec3 tf_position;
    flat int tf_instance;
    flat int tf_skirt;
} cout;

struct Corner {
    vec3 position;
    vec3 texcoord;
    vec2 cell;
    int foot; // tf_skirt of the vertex: 0 surface, 1 skirt, 2 skirt foot
};

Corner corner(int k) {
    return Corner(vin[k].position, vin[k].texcoord, vin[k].cell, cin[k].tf_skirt);
}

// a before b in a fixed order of their cell coordinates (then heights, for skirt edges).
bool before(Corner a, Corner b) {
    if (a.cell.x != b.cell.x)
        return a.cell.x < b.cell.x;
    if (a.cell.y != b.cell.y)
        return a.cell.y < b.cell.y;
    if (a.foot != b.foot)
        return a.foot > b.foot; // a skirt's foot before its top (the plane's lower z first)
    return a.position.z < b.position.z;
}

// Whether corner c is a vertex of a pole row (every one of which is the pole) on the globe.
bool onPole(PatchInstance p, Corner c) {
    if (RIDGE_SURFACE != 1 || c.cell.y != round(c.cell.y))
        return false;
    int row = u_anchor_sample.y + p.origin.y + int(round(c.cell.y * float(p.step)));
    return row == u_pole_rows.x || row == u_pole_rows.y;
}

// The point of edge a-b on the line cell[axis] = limit, the same whichever way round. On the
// globe a line of rows on a pole is the pole itself: the cut is the pole vertex (its height the
// sample past the line's, the pole row edge-extended), bit for bit what finer patches that
// have the pole row as samples draw there, so the cap closes on one point. And an edge from a
// pole runs along its other end's meridian: it meets the meridian of a column cut only at the
// pole, so that is the cut.
Corner cut(PatchInstance p, Corner a, Corner b, int axis, float limit) {
    if (before(b, a)) {
        Corner t = a;
        a = b;
        b = t;
    }
    precise float t = (limit - a.cell[axis]) / (b.cell[axis] - a.cell[axis]);
    Corner c;
    c.position = mix(a.position, b.position, t);
    c.texcoord = mix(a.texcoord, b.texcoord, t);
    c.cell = mix(a.cell, b.cell, t);
    c.cell[axis] = limit;
    c.foot = (a.foot == 2 && b.foot == 2) ? 2 : max(a.foot, b.foot);
    if (axis == 0 && (onPole(p, a) || onPole(p, b))) {
        c.position = onPole(p, a) ? a.position : b.position;
        return c;
    }
    // Along the surface, a skirt's top line or its foot line (not across a skirt: its
    // vertical edges never cross a row line).
    if (RIDGE_SURFACE == 1 && axis == 1 && a.foot == b.foot) {
        int row_delta = p.origin.y + int(round(limit * float(p.step)));
        int row = u_anchor_sample.y + row_delta;
        if (row == u_pole_rows.x || row == u_pole_rows.y) {
            Corner beyond = a.cell[axis] > limit ? a : b;
            vec3 up;
            c.position = framePoint(ivec2(0, row_delta),
                                    drawnHeight(p, ivec2(round(beyond.cell))), up);
            // A skirt's foot line: the pole lowered as the skirts' feet are, along its up.
            if (a.foot == 2)
                c.position = lowered(c.position, up, p.skirt_depth);
        }
    }
    return c;
}

bool same(Corner a, Corner b) {
    return a.cell == b.cell && a.position == b.position;
}

// Whether the polygon's area vanishes against its perimeter.
bool sliver(Corner poly[5], int count) {
    vec3 normal_sum = vec3(0.0);
    float perimeter = 0.0;
    for (int k = 0; k < count; ++k) {
        vec3 a = poly[k].position - poly[0].position, b = poly[(k + 1) % count].position - poly[0].position;
        normal_sum += cross(a, b);
        perimeter += length(poly[(k + 1) % count].position - poly[k].position);
    }
    return length(normal_sum) <= 1e-6 * perimeter * perimeter;
}

// Appends c unless it repeats the last corner.
void push(inout Corner poly[5], inout int n, Corner c) {
    if (n < 5 && (n == 0 || !same(poly[n - 1], c)))
        poly[n++] = c;
}

void emit(Corner c, int skirt) {
    vout.position = c.position;
    vout.texcoord = c.texcoord;
    vout.cell = c.cell;
    vout.level = vin[0].level;
    vout.layer = vin[0].layer;
    vout.factor = vin[0].factor;
    vout.skirt = skirt;
    cout.tf_position = c.position;
    cout.tf_instance = cin[0].tf_instance;
    // Every vertex of a skirt or wall is marked at least 1: a cut skirt triangle may start at
    // the skirt's top, which chunk.vert marks 0 like the surface sample it is, and captures tell
    // skirt triangles by their first vertex.
    cout.tf_skirt = skirt != 0 ? max(c.foot, 1) : c.foot;
    gl_Position = u_view_projection * vec4(c.position, 1.0);
    EmitVertex();
}

void main() {
    PatchInstance p = instances[cin[0].tf_instance];
    Corner poly[5];
    int count = 3;
    for (int k = 0; k < 3; ++k)
        poly[k] = corner(k);
    // West and north of the terrain (clipmap footprints only): the border is a grid line of
    // the footprint's level, so a triangle lies wholly on one side of it.
    for (int k = 0; k < 3; ++k)
        if (any(lessThan(poly[k].cell, p.valid_start)))
            return;
    // A triangle flat before the cut with three distinct corners (a clipmap level's perimeter
    // triangle, which closes a T-junction) is drawn as the unclipped draw would draw it: the
    // sliver rule below is for what the cut leaves.
    bool flat_before = !same(poly[0], poly[1]) && !same(poly[1], poly[2]) &&
                       !same(poly[0], poly[2]) && sliver(poly, 3);
    bool clipped[2] = bool[2](false, false);
    for (int axis = 0; axis < 2; ++axis) {
        if (p.valid_extent[axis] >= u_unclipped_extent)
            continue; // the patch does not reach past the valid extent on this side
        if (u_drop_beyond[axis]) {
            for (int k = 0; k < count; ++k)
                if (poly[k].cell[axis] > p.valid_extent[axis])
                    return;
            continue;
        }
        clipped[axis] = true;
        float limit = p.valid_extent[axis];
        Corner next[5];
        int n = 0;
        for (int k = 0; k < count; ++k) {
            Corner a = poly[k], b = poly[(k + 1) % count];
            bool a_in = a.cell[axis] <= limit, b_in = b.cell[axis] <= limit;
            if (a_in)
                push(next, n, a);
            if (a_in != b_in)
                push(next, n, cut(p, a, b, axis, limit));
        }
        // A cut that lands on a corner repeats it; repeated corners would make degenerate
        // triangles that count an edge twice.
        if (n > 1 && same(next[n - 1], next[0]))
            --n;
        count = n;
        for (int k = 0; k < n; ++k)
            poly[k] = next[k];
        if (count < 3)
            return;
    }
    int skirt = vin[0].skirt;
    // Nothing left of a surface triangle but a sliver on the line (a triangle of the padding
    // touching it): its area vanishes. Skirts are exempt: a skirt wall is as thin as its
    // depth, which over flat ground (Err and λ 0) is only the rounding margin, a centimetre
    // under cells that may be kilometres long — far below this relative threshold, yet the
    // wall is what closes the seam. Clipping a vertical wall by a vertical plane leaves a
    // narrower wall or nothing (count < 3 above), never a sliver of it.
    if (skirt == 0 && !flat_before && sliver(poly, count))
        return;

    for (int k = 1; k + 1 < count; ++k) {
        emit(poly[0], skirt);
        emit(poly[k], skirt);
        emit(poly[k + 1], skirt);
        EndPrimitive();
    }
    if (skirt != 0)
        return; // skirts are cut, not walled
    // Walls under every edge of the surface that lies on a clipping line: top on the edge,
    // foot skirt_depth below, like the skirts on the patch borders.
    for (int k = 0; k < count; ++k) {
        Corner a = poly[k], b = poly[(k + 1) % count];
        bool on_line = false;
        for (int axis = 0; axis < 2; ++axis) {
            float limit = p.valid_extent[axis];
            on_line = on_line || (clipped[axis] && a.cell[axis] == limit && b.cell[axis] == limit);
        }
        if (!on_line)
            continue;
        Corner a_foot = a, b_foot = b;
        a_foot.position = lowered(a.position, worldUp(a.position), p.skirt_depth);
        b_foot.position = lowered(b.position, worldUp(b.position), p.skirt_depth);
        a_foot.foot = 2;
        b_foot.foot = 2;
        a.foot = 1;
        b.foot = 1;
        emit(a, 2);
        emit(b, 2);
        emit(a_foot, 2);
        emit(b_foot, 2);
        EndPrimitive();
    }
}
