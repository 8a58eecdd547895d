#pragma once
// Glossary of ridge's data model. Names follow the papers (see docs/DESIGN.md).
//
// code            A 16-bit unsigned integer height sample. Heights in metres are
//                 metres = height_offset + height_scale * code  (HeightQuantization).
//                 For 8/16-bit integer input the mapping is exact.
// finest grid     The input raster after void filling, width x height samples, row-major,
//                 sample (x, y) with x to the east (columns) and y to the south (rows).
// valid extent    [0, width-1] x [0, height-1] in finest-grid samples. Everything outside is
//                 padding by edge extension (clamping) and must never be drawn.
// level l         0 = coarsest (one patch), L = level_count-1 = finest grid. Level l has
//                 sample spacing step(l) = 2^(L-l) finest samples.
// patch (l,x,y)   (C+1)^2 samples of level l, C = 2^n cells, covering level samples
//                 [x*C, x*C+C] x [y*C, y*C+C]; neighbours share their one-sample border.
// δ_l             Codec error bound at level l (metres): |decoded - exact level sample|.
// Err_Int(P)      Max deviation of P's interpolated surface from its children's samples.
// Err_Appr(P)     Err_Int(P) + max over children Err_Appr; 0 at the finest level.
// Err(P)          Err_Appr(P) + δ_l: bound on |P's surface - full-resolution sample|.
// λ(d)            Tessellation block error: deviation of a block's samples from the block
//                 triangulation simplified by 2^d (d = 1..block_levels).
