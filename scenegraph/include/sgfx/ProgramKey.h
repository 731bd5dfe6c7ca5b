#pragma once
#include "sgfx/Export.h"
#include <array>
#include <cstdint>
#include <iosfwd>
#include <string>
#include <string_view>
#include <unordered_map>

namespace sgfx {

enum class DrawMode : std::uint8_t; // Renderer.h

/// A set of MaterialFeature bits (ShaderComposer.h): which variant of the built-in material.
using FeatureMask = std::uint64_t;

/// One named bit field of a ProgramKey: `width` bits from bit `shift`.
struct SGFX_API ProgramKeyField {
    const char* name;
    unsigned shift;
    unsigned width;
    constexpr std::uint64_t max() const { return (std::uint64_t(1) << width) - 1; }
    constexpr std::uint64_t mask() const { return max() << shift; }
    constexpr bool fits(std::uint64_t value) const { return value <= max(); }
};

/// What an item's program is made from; ProgramKey::Base says which one.
enum class ProgramSource : std::uint8_t {
    Builtin,  ///< the built-in material (Base 0)
    Foreign,  ///< the application's ShaderProgram of the item's state
    Drawable, ///< a Drawable's own BaseShader
};

/// Which program an item draws with, as one 64-bit value of named fields (after Filament's
/// RenderPass CommandKey): equal keys mean one program, so Renderer::drawItems binds it once and
/// RenderQueue::sort groups items by it. Each field is written through with()/make(), which throw
/// std::length_error naming the field when a value does not fit: nothing is truncated, so two
/// programs never share a key by overflowing into a neighbour. Bit 63 is in no field: none() is
/// no item's key.
class SGFX_API ProgramKey {
public:
    /// MaterialFeature bits of the variant (every bit is checked to fit in ShaderComposer.h).
    static constexpr ProgramKeyField Features{"Features", 0, 37};
    /// DrawMode: depth and G-buffer passes draw other variants of the same item.
    static constexpr ProgramKeyField Mode{"Mode", 37, 2};
    /// The effects' snippet signature, interned (ProgramKeyTable::effects); 0 = no snippet.
    /// 2047 distinct snippet sets per view.
    static constexpr ProgramKeyField Effects{"Effects", 39, 11};
    /// The foreign program or drawable base shader, interned (ProgramKeyTable::base); 0 = built-in.
    /// 2047 distinct foreign programs per view.
    static constexpr ProgramKeyField Base{"Base", 50, 11};
    /// ProgramSource: a drawable's base shader never shares a key with a foreign program.
    static constexpr ProgramKeyField Source{"Source", 61, 2};
    static constexpr std::array<ProgramKeyField, 5> kFields{Features, Mode, Effects, Base, Source};
    static constexpr std::uint64_t kNoneBit = std::uint64_t(1) << 63;

    /// Fields lie inside 64 bits and no two overlap.
    static constexpr bool fieldsDisjoint() {
        std::uint64_t used = 0;
        for (const ProgramKeyField& f : kFields) {
            if (f.width == 0 || f.width >= 64 || f.shift + f.width > 64 || (used & f.mask())) return false;
            used |= f.mask();
        }
        return true;
    }
    static constexpr std::uint64_t usedBits() {
        std::uint64_t used = 0;
        for (const ProgramKeyField& f : kFields)
            used |= f.mask();
        return used;
    }

    /// The built-in material, no effects, no features, DrawMode::Main.
    constexpr ProgramKey() = default;
    /// Throws std::length_error naming the first field a value does not fit. Inline: the cull
    /// makes one per item.
    static constexpr ProgramKey make(ProgramSource source, std::uint32_t base, std::uint32_t effects,
                                     FeatureMask features, DrawMode mode = DrawMode{}) {
        return ProgramKey()
            .with(Features, features)
            .with(Mode, std::uint64_t(mode))
            .with(Effects, effects)
            .with(Base, base)
            .with(Source, std::uint64_t(source));
    }
    /// Matches no item's key (a draw loop's "no program yet").
    static constexpr ProgramKey none() { return ProgramKey(kNoneBit); }

    /// This key with `field` set to `value`; throws std::length_error naming the field when the
    /// value does not fit.
    constexpr ProgramKey with(const ProgramKeyField& field, std::uint64_t value) const {
        if (!field.fits(value)) throwTooWide(field, value);
        return ProgramKey((bits_ & ~field.mask()) | (value << field.shift));
    }
    constexpr std::uint64_t get(const ProgramKeyField& field) const {
        return (bits_ >> field.shift) & field.max();
    }
    constexpr FeatureMask features() const { return get(Features); }
    constexpr DrawMode mode() const { return DrawMode(get(Mode)); }
    constexpr std::uint32_t effects() const { return std::uint32_t(get(Effects)); }
    constexpr std::uint32_t base() const { return std::uint32_t(get(Base)); }
    constexpr ProgramSource source() const { return ProgramSource(get(Source)); }
    constexpr std::uint64_t bits() const { return bits_; }

    friend constexpr auto operator<=>(const ProgramKey&, const ProgramKey&) = default;

private:
    constexpr explicit ProgramKey(std::uint64_t bits)
        : bits_(bits) {}
    [[noreturn]] static void throwTooWide(const ProgramKeyField& field, std::uint64_t value);
    std::uint64_t bits_ = 0;
};

static_assert(ProgramKey::fieldsDisjoint(), "ProgramKey fields overlap or leave the 64 bits");
static_assert((ProgramKey::usedBits() & ProgramKey::kNoneBit) == 0, "none() must be no item's key");
static_assert(ProgramKey::Source.fits(std::uint64_t(ProgramSource::Drawable)));
// Every field reads back what was written at its largest value, untouched by its neighbours.
static_assert(ProgramKey::make(ProgramSource::Drawable, 0x7ff, 0x7ff, 0x1fffffffff).base() == 0x7ff &&
              ProgramKey::make(ProgramSource::Drawable, 0x7ff, 0x7ff, 0x1fffffffff).effects() == 0x7ff &&
              ProgramKey::make(ProgramSource::Drawable, 0x7ff, 0x7ff, 0x1fffffffff).features() ==
                  0x1fffffffff &&
              ProgramKey::make(ProgramSource::Drawable, 0x7ff, 0x7ff, 0x1fffffffff).source() ==
                  ProgramSource::Drawable);

/// "Features=0x110 Mode=0 Effects=3 Base=1 Source=Foreign" (test failures, logs).
SGFX_API std::ostream& operator<<(std::ostream& out, const ProgramKey& key);

/// Small dense ids for what a ProgramKey names by identity (foreign programs, drawable base
/// shaders) or by text (effect signatures). A RenderQueue owns one and clears it with the queue,
/// so ids are dense per view and frame and never grow over a session.
///
/// Guarantee: from one clear() to the next, distinct live objects get distinct ids. Nothing keeps
/// a key across a clear() (the composer caches programs by their text), so an address reused by
/// a new object after the old one died only needs to be distinct within one queue's items, and it
/// is: the queue's states hold the foreign programs they name, and a drawable's base shader is
/// the same object for the whole frame (Drawable::baseShader).
class SGFX_API ProgramKeyTable {
public:
    /// Base id of a foreign ShaderProgram or a Drawable's BaseShader, from 1 (0 = built-in, for
    /// null). Throws std::length_error when the Base field is full.
    std::uint32_t base(const void* source);
    /// Effects id of a snippet signature, from 1 ("" = no snippet = 0). Throws std::length_error
    /// when the Effects field is full.
    std::uint32_t effects(std::string_view signature);
    std::size_t bases() const { return bases_.size(); }
    std::size_t signatures() const { return signatures_.size(); }
    void clear();

private:
    std::unordered_map<const void*, std::uint32_t> bases_;
    std::unordered_map<std::string, std::uint32_t> signatures_;
    // Consecutive items mostly name the same base: one-entry cache before the map.
    const void* lastBase_ = nullptr;
    std::uint32_t lastBaseId_ = 0;
};

} // namespace sgfx
