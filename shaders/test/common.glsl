// Included by test/quadrants.frag: checks that include expansion compiles.

// 1 where `coordinate` (pixels) is past the middle of `extent` (pixels), else 0.
float pastMiddle(float coordinate, float extent)
{
    return coordinate >= 0.5 * extent ? 1.0 : 0.0;
}
