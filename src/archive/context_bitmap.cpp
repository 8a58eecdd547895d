#include "context_bitmap.h"

#include "ridge/codec/range_coder.h"

namespace ridge::archive::detail {

namespace {

constexpr int kTemplateBits = 10;

// Plane bits with two rows and columns of zeros around them, so that every template read is
// in bounds and reads 0 outside the patch.
class PaddedPlane {
  public:
    explicit PaddedPlane(int n) : stride_(n + 4), bits_(size_t(n + 4) * size_t(n + 2), 0) {}
    uint8_t* row(int y) { return bits_.data() + size_t(y + 2) * stride_ + 2; }
    ptrdiff_t stride() const { return stride_; }

  private:
    ptrdiff_t stride_;
    std::vector<uint8_t> bits_;
};

// The ten coded neighbours of *at, one bit each.
inline int templateOf(const uint8_t* at, ptrdiff_t s)
{
    return at[-1] | at[-2] << 1 | at[-s - 2] << 2 | at[-s - 1] << 3 | at[-s] << 4 |
           at[-s + 1] << 5 | at[-s + 2] << 6 | at[-2 * s - 1] << 7 | at[-2 * s] << 8 |
           at[-2 * s + 1] << 9;
}

// Visits every bit of every plane in coding order with its context; `code(model, bit)` codes
// or decodes it and returns the bit.
template <class Code>
void traverse(int n, size_t planes, const std::vector<uint8_t*>& values, Code code)
{
    std::vector<rc::AdaptiveCdf<2>> models(size_t(2) << kTemplateBits);
    PaddedPlane first(n);
    for (size_t p = 0; p < planes; ++p) {
        for (auto& m : models)
            m.reset();
        PaddedPlane plane(n);
        for (int y = 0; y < n; ++y) {
            uint8_t* row = plane.row(y);
            const uint8_t* first_row = first.row(y);
            uint8_t* out = values[p] + size_t(y) * n;
            for (int x = 0; x < n; ++x) {
                const int ctx = templateOf(row + x, plane.stride()) |
                                (p > 0 ? first_row[x] << kTemplateBits : 0);
                row[x] = static_cast<uint8_t>(code(models[size_t(ctx)], out[x] != 0));
                out[x] = row[x];
            }
        }
        if (p == 0)
            first = plane;
    }
}

} // namespace

std::vector<uint8_t> encodeContextBitmap(const std::vector<const std::vector<uint8_t>*>& planes,
                                         int n)
{
    std::vector<uint8_t> stream;
    rc::Encoder enc(stream);
    std::vector<std::vector<uint8_t>> copies;
    copies.reserve(planes.size()); // values point into them
    std::vector<uint8_t*> values;
    for (const auto* plane : planes) {
        copies.push_back(*plane); // traverse writes back the 0/1 bit it coded
        values.push_back(copies.back().data());
    }
    traverse(n, planes.size(), values, [&](rc::AdaptiveCdf<2>& m, int bit) {
        enc.encode(m, bit);
        return bit;
    });
    enc.finish();
    return stream;
}

bool decodeContextBitmap(const uint8_t* data, size_t size, int n,
                         const std::vector<std::vector<uint8_t>*>& planes)
{
    rc::Decoder dec(data, size);
    std::vector<uint8_t*> values;
    for (auto* plane : planes) {
        plane->assign(size_t(n) * n, 0);
        values.push_back(plane->data());
    }
    traverse(n, planes.size(), values, [&](rc::AdaptiveCdf<2>& m, int) { return dec.decode(m); });
    return dec.ok() && dec.remaining() == 0;
}

} // namespace ridge::archive::detail
