#include "patch_textures.h"

#include "projected_lattice.h"

#include "ridge/core/error.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>

namespace ridge::render {

bool PatchTextures::waterMaps(const archive::ArchiveReader& reader)
{
    return reader.storesSampleFlags() && reader.metadata().water.samples > 0;
}

double PatchTextures::bytesPerSlot(int patch_size, const TessellationBlockLayout& layout,
                                   bool water_maps, const HeightCodec* gpu_codec)
{
    const GpuDecoderInfo* decoder = gpu_codec ? findGpuDecoder(*gpu_codec) : nullptr;
    const double decoder_bytes = decoder ? decoder->bytes_per_slot(patch_size) : 0.0;
    const double n = patch_size;
    const double blocks = double(layout.blocksPerSide());
    // Heights R16UI and normals RGBA8 (n²), block errors RGBA32F, the kept-nodata cell mask
    // R8UI ((n−1)², allocated for every slot) and its flag, the water map R8UI (n², only for
    // archives with water).
    return n * n * (2.0 + 4.0 + (water_maps ? 1.0 : 0.0)) + blocks * blocks * 16.0 +
           (n - 1) * (n - 1) + 1.0 + decoder_bytes;
}

int PatchTextures::slotCount(const archive::ArchiveReader& reader, double scheme_slot_bytes,
                             double vram_budget_mb, int max_slots, const HeightCodec* gpu_codec,
                             double scheme_fixed_bytes)
{
    const int n = reader.geometry().patchSize();
    const double bytes_per_slot =
        bytesPerSlot(n, reader.blockLayout(), waterMaps(reader), gpu_codec) + scheme_slot_bytes;
    GLint max_layers = 256;
    glGetIntegerv(GL_MAX_ARRAY_TEXTURE_LAYERS, &max_layers);
    const double by_budget = std::floor(
        std::max(vram_budget_mb * 1024.0 * 1024.0 - scheme_fixed_bytes, 0.0) / bytes_per_slot);
    const int wanted = int(std::min({double(max_slots), by_budget, double(max_layers)}));
    const int minimum = 4;
    if (wanted < minimum) {
        char message[160];
        std::snprintf(
            message, sizeof message,
            ": patches of %d^2 samples need %.3g MB of texture memory at least; the budget "
            "is %.3g MB",
            n, (minimum * bytes_per_slot + scheme_fixed_bytes) / 1048576.0, vram_budget_mb);
        throw Error(reader.path() + message);
    }
    return wanted;
}

PatchTextures::PatchTextures(int patch_size, const TessellationBlockLayout& layout, int levels,
                             int slots, const HeightQuantization& quantization,
                             const HeightCodec* gpu_codec, bool water_maps)
    : n_(patch_size), layout_(layout), levels_(levels), quantization_(quantization),
      lambda_max_(size_t(slots), 0.f), lambda_cap_(size_t(slots), 0.f),
      generation_(size_t(slots), 0), masked_(size_t(slots), 0)
{
    const int B = layout_.blocksPerSide();
    glTextureStorage3D(heights_.id(), 1, GL_R16UI, n_, n_, slots);
    glTextureParameteri(heights_.id(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTextureParameteri(heights_.id(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTextureStorage3D(normals_.id(), 1, GL_RGBA8_SNORM, n_, n_, slots);
    glTextureParameteri(normals_.id(), GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTextureParameteri(normals_.id(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTextureParameteri(normals_.id(), GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTextureParameteri(normals_.id(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glTextureStorage3D(block_errors_.id(), 1, GL_RGBA32F, B, B, slots);
    glTextureParameteri(block_errors_.id(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTextureParameteri(block_errors_.id(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    const int C = n_ - 1;
    glTextureStorage3D(cell_masks_.id(), 1, GL_R8UI, C, C, slots);
    glTextureStorage1D(mask_flags_.id(), 1, GL_R8UI, slots);
    water_maps_allocated_ = water_maps;
    glTextureStorage3D(water_maps_.id(), 1, GL_R8UI, n_, n_, water_maps ? slots : 1);
    for (GLuint t : {cell_masks_.id(), mask_flags_.id(), water_maps_.id()}) {
        glTextureParameteri(t, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glTextureParameteri(t, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    }
    const std::vector<uint8_t> no_masks(size_t(slots), 0);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTextureSubImage1D(mask_flags_.id(), 0, 0, slots, GL_RED_INTEGER, GL_UNSIGNED_BYTE,
                        no_masks.data());
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glNamedBufferStorage(lambda_max_bits_.id(), GLsizeiptr(slots) * GLsizeiptr(sizeof(uint32_t)),
                         nullptr, GL_DYNAMIC_STORAGE_BIT);
    gpu::checkGlError("patch textures: texture arrays");
    normal_program_ = gpu::ShaderProgram({{GL_COMPUTE_SHADER, "patch_normals.comp"}});
    if (gpu_codec) {
        const GpuDecoderInfo* decoder = findGpuDecoder(*gpu_codec);
        if (!decoder)
            throw Error(std::string("internal error: no GPU decoder for the ") + gpu_codec->name() +
                        " codec");
        decoder_ = decoder->make(*gpu_codec, n_, slots);
        block_error_program_ = gpu::ShaderProgram({{GL_COMPUTE_SHADER, "block_errors.comp"}});
    }
}

PatchTextures::~PatchTextures()
{
    for (const PendingReadback& p : pending_)
        glDeleteSync(p.fence);
}

void PatchTextures::uploadBlockErrors(const stream::DecodedPatch& patch, int slot, float lambda_cap)
{
    // λ(d) as one RGBA texel per block; missing levels (D < 4) stay 0 and are never read.
    const int B = layout_.blocksPerSide(), D = layout_.levels();
    std::vector<float> texels(size_t(B) * B * 4, 0.f);
    for (int b = 0; b < B * B; ++b)
        for (int d = 0; d < levels_; ++d)
            texels[size_t(b) * 4 + d] = patch.block_errors[size_t(b) * D + d];
    glTextureSubImage3D(block_errors_.id(), 0, 0, 0, slot, B, B, 1, GL_RGBA, GL_FLOAT,
                        texels.data());
    // The tessellator drops at most λ max; λ never exceeds the patch's height range (every
    // simplified vertex is a patch sample), which also tames saturated values.
    const float lambda_max = *std::max_element(texels.begin(), texels.end());
    lambda_max_[size_t(slot)] = std::min(lambda_max, lambda_cap);
}

void PatchTextures::uploadMasks(const stream::DecodedPatch& patch, int slot)
{
    const PatchSampleFlags& water = patch.sample_flags;
    // Mixed flags may mark only filled voids (kSampleFilled): no water to map then.
    const bool water_map = water.kind == PatchSampleFlags::Kind::Mixed &&
                           std::any_of(water.flags.begin(), water.flags.end(),
                                       [](uint8_t f) { return (f & kSampleWater) != 0; });
    if (water_map && !water_maps_allocated_)
        throw Error("internal error: a patch with water arrived at a renderer without water maps");
    const uint8_t flag = uint8_t((patch.drawable_cells.empty() ? 0 : 1) | (water_map ? 2 : 0) |
                                 (water.kind == PatchSampleFlags::Kind::AllWater ? 4 : 0));
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1); // rows of C or n bytes
    if (flag & 1) {
        const int C = n_ - 1;
        glTextureSubImage3D(cell_masks_.id(), 0, 0, 0, slot, C, C, 1, GL_RED_INTEGER,
                            GL_UNSIGNED_BYTE, patch.drawable_cells.data());
    }
    if (water_map)
        glTextureSubImage3D(water_maps_.id(), 0, 0, 0, slot, n_, n_, 1, GL_RED_INTEGER,
                            GL_UNSIGNED_BYTE, water.flags.data());
    if (masked_[size_t(slot)] != flag)
        glTextureSubImage1D(mask_flags_.id(), 0, slot, 1, GL_RED_INTEGER, GL_UNSIGNED_BYTE, &flag);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    masked_[size_t(slot)] = flag;
}

void PatchTextures::computeNormals(int slot, const std::array<int, 4>& neighbours,
                                   double cell_metres_i, double cell_metres_j, double latitude0,
                                   double latitude_step)
{
    normal_program_.use();
    glUniform1i(normal_program_.uniform("u_projected"), 0);
    glUniform2f(normal_program_.uniform("u_cell_metres"), float(cell_metres_i),
                float(cell_metres_j));
    glUniform2f(normal_program_.uniform("u_latitude"), float(latitude0), float(latitude_step));
    dispatchNormals(slot, neighbours);
}

void PatchTextures::setGridAxes(const lod::ProjectedGrid& grid)
{
    grid_ = &grid;
    lattice_ = absoluteLatticeTexture(grid);
}

void PatchTextures::computeNormalsOnGrid(int slot, const std::array<int, 4>& neighbours,
                                         int64_t column0, int64_t row0, int64_t step)
{
    if (!grid_)
        throw Error("internal error: computeNormalsOnGrid without setGridAxes");
    normal_program_.use();
    glUniform1i(normal_program_.uniform("u_projected"), 1);
    glUniform2i(normal_program_.uniform("u_patch_origin"), int(column0), int(row0));
    glUniform1i(normal_program_.uniform("u_patch_step"), int(step));
    glUniform2i(normal_program_.uniform("u_lattice_first"), grid_->firstColumn(),
                grid_->firstRow());
    glUniform1i(normal_program_.uniform("u_lattice_step"), grid_->step());
    glUniform2i(normal_program_.uniform("u_lattice_nodes"), grid_->nodesX(), grid_->nodesY());
    glUniform1f(normal_program_.uniform("u_polar_ratio"),
                float(1.0 / (1.0 - grid_->ellipsoid().e2())));
    glBindTextureUnit(kLatticeNormalsTextureUnit, lattice_->id());
    dispatchNormals(slot, neighbours);
}

void PatchTextures::dispatchNormals(int slot, const std::array<int, 4>& neighbours)
{
    glBindTextureUnit(0, heights_.id());
    glBindImageTexture(0, normals_.id(), 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_RGBA8_SNORM);
    glUniform1i(normal_program_.uniform("u_layer"), slot);
    glUniform1i(normal_program_.uniform("u_size"), n_);
    glUniform1f(normal_program_.uniform("u_height_scale"), float(quantization_.scale));
    glUniform4i(normal_program_.uniform("u_neighbour_layers"), neighbours[0], neighbours[1],
                neighbours[2], neighbours[3]);
    glDispatchCompute(GLuint(n_ + 7) / 8, GLuint(n_ + 7) / 8, 1);
}

void PatchTextures::upload(const stream::DecodedPatch& patch, int slot, float lambda_cap)
{
    ++generation_[size_t(slot)];
    // Rows of 2^n + 1 16-bit codes are not 4-byte aligned.
    glPixelStorei(GL_UNPACK_ALIGNMENT, 2);
    glTextureSubImage3D(heights_.id(), 0, 0, 0, slot, n_, n_, 1, GL_RED_INTEGER, GL_UNSIGNED_SHORT,
                        patch.codes.data());
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    uploadBlockErrors(patch, slot, lambda_cap);
    uploadMasks(patch, slot);
}

void PatchTextures::decodeOnGpu(const stream::DecodedPatch& patch, int parent_slot, int slot,
                                int steps, float lambda_cap)
{
    ++generation_[size_t(slot)];
    uploadMasks(patch, slot);
    const PatchId p = patch.id;
    decoder_->decode(*patch.gpu_payload,
                     {heights_.id(), slot, parent_slot, p.childIndex(), p.level}, steps);
    // The passes below (and children decoded later in this batch) read the codes.
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    if (!patch.block_errors.empty())
        uploadBlockErrors(patch, slot, lambda_cap);
    else
        deriveBlockErrors(slot, lambda_cap);
    gpu::checkGlError("patch textures: GPU decode");
}

void PatchTextures::refine(PatchId p, int slot, int steps, float lambda_cap)
{
    ++generation_[size_t(slot)];
    decoder_->refine({heights_.id(), slot, -1, p.childIndex(), p.level}, steps);
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    deriveBlockErrors(slot, lambda_cap);
    gpu::checkGlError("patch textures: refine");
}

void PatchTextures::deriveBlockErrors(int slot, float lambda_cap)
{
    const uint32_t zero = 0;
    glNamedBufferSubData(lambda_max_bits_.id(), GLintptr(slot) * GLintptr(sizeof(uint32_t)),
                         sizeof(uint32_t), &zero);
    block_error_program_.use();
    glBindTextureUnit(0, heights_.id());
    glBindImageTexture(2, block_errors_.id(), 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, lambda_max_bits_.id());
    glUniform1i(block_error_program_.uniform("u_layer"), slot);
    glUniform1i(block_error_program_.uniform("u_n"), n_);
    glUniform1i(block_error_program_.uniform("u_block_cells"), layout_.block_cells);
    glUniform1i(block_error_program_.uniform("u_blocks_per_side"), layout_.blocksPerSide());
    glUniform1i(block_error_program_.uniform("u_levels"), levels_);
    glUniform1d(block_error_program_.uniform("u_height_scale"), quantization_.scale);
    const GLuint groups = GLuint(layout_.blocksPerSide() + 7) / 8;
    glDispatchCompute(groups, groups, 1);
    // Until the readback: the height range bounds λ.
    lambda_max_[size_t(slot)] = lambda_cap;
    lambda_cap_[size_t(slot)] = lambda_cap;
    derived_in_batch_.push_back({slot, generation_[size_t(slot)]});
}

size_t PatchTextures::uploadBytes(const stream::DecodedPatch& patch) const
{
    const size_t B = size_t(layout_.blocksPerSide());
    const size_t lambda = patch.block_errors.empty() ? 0 : B * B * 4 * sizeof(float);
    // Kept nodata: the C x C mask and the slot's flag; water: the n x n bitmap and the flag;
    // other patches send nothing (at most a one-byte flag reset when their slot held a masked
    // patch, not counted).
    const size_t mask = (patch.drawable_cells.empty() ? 0 : patch.drawable_cells.size() + 1) +
                        patch.sample_flags.flags.size() +
                        (patch.sample_flags.kind == PatchSampleFlags::Kind::AllWater ? 1 : 0);
    if (patch.decodesOnGpu())
        return patch.gpu_payload->uploadBytes() + lambda + mask;
    return patch.codes.size() * sizeof(uint16_t) + lambda + mask;
}

void PatchTextures::finishUploads()
{
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT |
                    GL_BUFFER_UPDATE_BARRIER_BIT);
    if (derived_in_batch_.empty())
        return;
    PendingReadback readback{nullptr, gpu::GlBuffer(), {}};
    const GLsizeiptr bytes = GLsizeiptr(lambda_max_.size() * sizeof(uint32_t));
    glNamedBufferStorage(readback.copy.id(), bytes, nullptr, 0);
    glCopyNamedBufferSubData(lambda_max_bits_.id(), readback.copy.id(), 0, 0, bytes);
    readback.fence = glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
    readback.slots.swap(derived_in_batch_);
    pending_.push_back(std::move(readback));
}

void PatchTextures::collect()
{
    while (!pending_.empty()) {
        PendingReadback& oldest = pending_.front();
        // Flush once so that the fence is sure to signal; a zero timeout never waits.
        const GLenum state = glClientWaitSync(oldest.fence, GL_SYNC_FLUSH_COMMANDS_BIT, 0);
        if (state != GL_ALREADY_SIGNALED && state != GL_CONDITION_SATISFIED)
            return;
        std::vector<uint32_t> bits(lambda_max_.size());
        glGetNamedBufferSubData(oldest.copy.id(), 0, GLsizeiptr(bits.size() * sizeof(uint32_t)),
                                bits.data());
        for (const PendingSlot& s : oldest.slots) {
            if (generation_[size_t(s.slot)] != s.generation)
                continue; // re-used since
            float m;
            std::memcpy(&m, &bits[size_t(s.slot)], sizeof m);
            lambda_max_[size_t(s.slot)] = std::min(m, lambda_cap_[size_t(s.slot)]);
        }
        glDeleteSync(oldest.fence);
        pending_.erase(pending_.begin());
    }
}

std::vector<uint16_t> PatchTextures::readCodes(int slot) const
{
    std::vector<uint16_t> codes(size_t(n_) * n_);
    glPixelStorei(GL_PACK_ALIGNMENT, 2);
    glGetTextureSubImage(heights_.id(), 0, 0, 0, slot, n_, n_, 1, GL_RED_INTEGER, GL_UNSIGNED_SHORT,
                         GLsizei(codes.size() * sizeof(uint16_t)), codes.data());
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    gpu::checkGlError("patch textures: read codes");
    return codes;
}

std::vector<float> PatchTextures::readBlockErrors(int slot) const
{
    const int B = layout_.blocksPerSide(), D = layout_.levels();
    std::vector<float> texels(size_t(B) * B * 4);
    glGetTextureSubImage(block_errors_.id(), 0, 0, 0, slot, B, B, 1, GL_RGBA, GL_FLOAT,
                         GLsizei(texels.size() * sizeof(float)), texels.data());
    gpu::checkGlError("patch textures: read block errors");
    std::vector<float> lambda(size_t(B) * B * D, 0.f);
    for (int b = 0; b < B * B; ++b)
        for (int d = 0; d < std::min(D, 4); ++d)
            lambda[size_t(b) * D + d] = texels[size_t(b) * 4 + d];
    return lambda;
}

std::vector<int8_t> PatchTextures::readNormals(int slot) const
{
    std::vector<int8_t> texels(size_t(n_) * n_ * 4);
    glGetTextureSubImage(normals_.id(), 0, 0, 0, slot, n_, n_, 1, GL_RGBA, GL_BYTE,
                         GLsizei(texels.size()), texels.data());
    gpu::checkGlError("patch textures: read normals");
    return texels;
}

void PatchTextures::bind() const
{
    glBindTextureUnit(0, heights_.id());
    glBindTextureUnit(1, normals_.id());
    glBindTextureUnit(2, block_errors_.id());
    glBindTextureUnit(4, cell_masks_.id());
    glBindTextureUnit(5, mask_flags_.id());
    glBindTextureUnit(6, water_maps_.id());
}

} // namespace ridge::render
