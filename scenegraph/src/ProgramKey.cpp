#include "sgfx/ProgramKey.h"

#include <ostream>
#include <stdexcept>

namespace sgfx {

void ProgramKey::throwTooWide(const ProgramKeyField& field, std::uint64_t value) {
    throw std::length_error("sgfx: ProgramKey field " + std::string(field.name) + " is " +
                            std::to_string(field.width) + " bits wide; " + std::to_string(value) +
                            " does not fit (max " + std::to_string(field.max()) + ")");
}

std::ostream& operator<<(std::ostream& out, const ProgramKey& key) {
    static const char* const sources[] = {"Builtin", "Foreign", "Drawable", "?"};
    const auto flags = out.flags();
    out << "Features=0x" << std::hex << key.features() << std::dec << " Mode=" << key.get(ProgramKey::Mode)
        << " Effects=" << key.effects() << " Base=" << key.base()
        << " Source=" << sources[key.get(ProgramKey::Source)];
    if (key.bits() & ProgramKey::kNoneBit) out << " (none)";
    out.flags(flags);
    return out;
}

std::uint32_t ProgramKeyTable::base(const void* source) {
    if (!source) return 0;
    if (source == lastBase_) return lastBaseId_;
    auto [it, added] = bases_.try_emplace(source, std::uint32_t(bases_.size() + 1));
    if (added && !ProgramKey::Base.fits(it->second)) {
        bases_.erase(it);
        throw std::length_error("sgfx: more than " + std::to_string(ProgramKey::Base.max()) +
                                " foreign programs and drawable base shaders in one view (ProgramKey field "
                                "Base is " +
                                std::to_string(ProgramKey::Base.width) + " bits wide)");
    }
    lastBase_ = source;
    lastBaseId_ = it->second;
    return it->second;
}

std::uint32_t ProgramKeyTable::effects(std::string_view signature) {
    if (signature.empty()) return 0;
    auto [it, added] = signatures_.try_emplace(std::string(signature), std::uint32_t(signatures_.size() + 1));
    if (added && !ProgramKey::Effects.fits(it->second)) {
        signatures_.erase(it);
        throw std::length_error("sgfx: more than " + std::to_string(ProgramKey::Effects.max()) +
                                " distinct effect snippet sets in one view (ProgramKey field Effects is " +
                                std::to_string(ProgramKey::Effects.width) + " bits wide)");
    }
    return it->second;
}

void ProgramKeyTable::clear() {
    bases_.clear();
    signatures_.clear();
    lastBase_ = nullptr;
    lastBaseId_ = 0;
}

} // namespace sgfx
