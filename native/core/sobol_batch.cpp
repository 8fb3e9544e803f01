// The batched Sobol' points (sobol_batch.h): patterns.h's ReverseBits32, OwenScrambleReversed and SobolByteProduct in
// Highway lanes of uint32, compiled once per instruction set (foreach_target.h re-includes this file).
#include "core/sobol_batch.h"

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "core/sobol_batch.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
// (foreach_target.h first, then highway.h: Highway's dispatch idiom.)
#include <hwy/highway.h>

#include <algorithm>

#include "core/patterns.h"

HWY_BEFORE_NAMESPACE();
namespace sphrect {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using DU = hn::ScalableTag<uint32_t>;
using VU = hn::Vec<DU>;

// ReverseBits32: bits within bytes by three swaps, then the bytes reversed.
HWY_INLINE VU ReverseBitsV(DU d, VU v) {
    auto swap = [&](VU x, uint32_t mask, auto shift) {
        const VU m = hn::Set(d, mask);
        return hn::Or(hn::And(hn::ShiftRight<decltype(shift)::value>(x), m),
                      hn::ShiftLeft<decltype(shift)::value>(hn::And(x, m)));
    };
    v = swap(v, 0x55555555u, std::integral_constant<int, 1>{});
    v = swap(v, 0x33333333u, std::integral_constant<int, 2>{});
    v = swap(v, 0x0f0f0f0fu, std::integral_constant<int, 4>{});
    return hn::Or(hn::Or(hn::ShiftLeft<24>(v), hn::ShiftRight<24>(v)),
                  hn::Or(hn::And(hn::ShiftLeft<8>(v), hn::Set(d, 0xff0000u)),
                         hn::And(hn::ShiftRight<8>(v), hn::Set(d, 0xff00u))));
}

// OwenScrambleReversed (Burley 2020's constants, patterns.h).
HWY_INLINE VU OwenScrambleReversedV(DU d, VU x, VU seed) {
    x = hn::Add(x, seed);
    x = hn::Xor(x, hn::Mul(x, hn::Set(d, 0x6c50b47cu)));
    x = hn::Xor(x, hn::Mul(x, hn::Set(d, 0xb82f1e52u)));
    x = hn::Xor(x, hn::Mul(x, hn::Set(d, 0xc7afe638u)));
    x = hn::Xor(x, hn::Mul(x, hn::Set(d, 0x8d22f6e6u)));
    return x;
}

// SobolByteProduct of the bit-reversed tables: one gather per byte of the index.
HWY_INLINE VU SobolDimension1ReversedV(DU d, VU index) {
    const hn::RebindToSigned<DU> di;
    const auto& t = pattern_detail::kSobolDimension1ReversedTables.table;
    const VU low = hn::Set(d, 0xffu);
    auto lookup = [&](int b, VU byte) { return hn::GatherIndex(d, t[b], hn::BitCast(di, byte)); };
    return hn::Xor(hn::Xor(lookup(0, hn::And(index, low)), lookup(1, hn::And(hn::ShiftRight<8>(index), low))),
                   hn::Xor(lookup(2, hn::And(hn::ShiftRight<16>(index), low)), lookup(3, hn::ShiftRight<24>(index))));
}

// BitsToUnitFloat: the top 24 bits as a fraction.
HWY_INLINE hn::Vec<hn::Rebind<float, DU>> UnitFloatV(DU, VU bits) {
    const hn::Rebind<float, DU> df;
    const hn::RebindToSigned<DU> di;
    return hn::Mul(hn::ConvertTo(df, hn::BitCast(di, hn::ShiftRight<8>(bits))), hn::Set(df, 0x1p-24f));
}

void ScrambledSobolPointsBatchImpl(const SobolLanes& lanes, size_t n, Point2<float>* out) {
    const DU d;
    const hn::Rebind<float, DU> df;
    constexpr size_t kMaxLanes = HWY_MAX_BYTES / sizeof(uint32_t);
    HWY_ALIGN float xy[2 * kMaxLanes];
    const size_t N = hn::Lanes(d);
    for (size_t i = 0; i < n; i += N) {
        const size_t count = std::min(N, n - i);
        HWY_ALIGN uint32_t tail[kMaxLanes] = {};
        auto load = [&](const uint32_t* p) {  // (a short batch's lanes past the end read 0)
            if (count == N) return hn::LoadU(d, p + i);
            std::copy(p + i, p + i + count, tail);
            return hn::Load(d, tail);
        };
        VU index = load(lanes.index);
        // OwenScramble where shuffled: the scramble of the index's bit-reversed digits.
        const VU shuffled = ReverseBitsV(d, OwenScrambleReversedV(d, ReverseBitsV(d, index), load(lanes.shuffle_seed)));
        index = hn::IfThenElse(hn::MaskFromVec(load(lanes.shuffled)), shuffled, index);
        const VU x = ReverseBitsV(d, OwenScrambleReversedV(d, index, load(lanes.key_x)));
        const VU y = ReverseBitsV(d, OwenScrambleReversedV(d, SobolDimension1ReversedV(d, index), load(lanes.key_y)));
        float* dst = count == N ? reinterpret_cast<float*>(out + i) : xy;
        hn::StoreInterleaved2(UnitFloatV(d, x), UnitFloatV(d, y), df, dst);
        if (count < N) std::copy(xy, xy + 2 * count, reinterpret_cast<float*>(out + i));
    }
}

}  // namespace HWY_NAMESPACE
}  // namespace sphrect
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace sphrect {

HWY_EXPORT(ScrambledSobolPointsBatchImpl);

void ScrambledSobolPointsBatch(const SobolLanes& lanes, size_t n, Point2<float>* out) {
    if (n == 0) return;
    HWY_DYNAMIC_DISPATCH(ScrambledSobolPointsBatchImpl)(lanes, n, out);
}

}  // namespace sphrect
#endif
