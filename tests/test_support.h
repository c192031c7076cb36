// tests/test_support.h — doctest printing for Unison types, so failed checks show "pivot_limit", not a number.
#pragma once

#include <doctest/doctest.h>

#include <unison/lcp.h>

namespace doctest {
template <>
struct StringMaker<unison::LcpStatus> {
    static String convert(unison::LcpStatus s) { return unison::statusName(s); }
};
}  // namespace doctest
