// Names of the enums that users pick by string (techniques, patterns, MIS modes, ...).
#pragma once

#include <string>

namespace sphrect {

// The value of `values` whose name_of(value) is `name`; false (and *out untouched) when there is none.
template <class Values, class E, class NameOf>
bool ParseEnumName(const std::string& name, const Values& values, NameOf name_of, E* out) {
    for (E v : values)
        if (name == name_of(v)) { *out = v; return true; }
    return false;
}

}  // namespace sphrect
