// Names of the enums that users pick by string (techniques, patterns, MIS modes, ...).
#pragma once

#include <array>
#include <cstddef>
#include <stdexcept>
#include <string>

namespace sphrect {

// The value of `values` whose name_of(value) is `name`; false (and *out untouched) when there is none.
template <class Values, class E, class NameOf>
bool ParseEnumName(const std::string& name, const Values& values, NameOf name_of, E* out) {
    for (E v : values)
        if (name == name_of(v)) {
            *out = v;
            return true;
        }
    return false;
}

// The names of `values`, quoted and comma-separated, for error messages: "'a', 'b', 'c'".
template <class Values, class NameOf>
std::string EnumNameList(const Values& values, NameOf name_of) {
    std::string s;
    for (auto v : values) s += std::string(s.empty() ? "'" : ", '") + name_of(v) + "'";
    return s;
}

// ParseEnumName, or std::invalid_argument (Python: ValueError) naming the valid values:
// "unknown <what> '<name>'; valid <plural>: 'a', 'b'".
template <class Values, class E, class NameOf>
void ParseEnumNameOrThrow(const std::string& what, const std::string& plural, const std::string& name,
                          const Values& values, NameOf name_of, E* out) {
    if (!ParseEnumName(name, values, name_of, out))
        throw std::invalid_argument("unknown " + what + " '" + name + "'; valid " + plural + ": " +
                                    EnumNameList(values, name_of));
}

// ParseEnumNameOrThrow for an enum whose values are 0, 1, ... named by `names` in that order (the renderer's k*Names
// lists); returns the value.
template <class Enum, size_t N>
Enum ParseNameOrThrow(const std::string& what, const std::string& plural, const std::string& name,
                      const char* const (&names)[N]) {
    std::array<Enum, N> values;
    for (size_t i = 0; i < N; ++i) values[i] = Enum(i);
    Enum out{};
    ParseEnumNameOrThrow(
        what, plural, name, values, [&](Enum e) { return names[size_t(e)]; }, &out);
    return out;
}

}  // namespace sphrect
