// tests/test_step_support.cpp — core/step_support: warm-start masks round-trip through an LCP basis, the cache
// finds entries by key only, touch events are set differences, the state writer is little-endian and field-wise.
#include "test_support.h"

#include "step_support.h"

#include <algorithm>
#include <cmath>

using namespace unison;

TEST_SUITE("step_support") {

TEST_CASE("a basis stored as masks comes back as the same basis") {
    const int nc = 3, k = 4;
    // normal 1, tangent 2 of contact 0 (index 3 + 0*4 + 2), slack of contact 2 (3 + 12 + 2).
    const std::vector<int> basis{1, 5, 17};
    std::vector<ContactKey> keys(3);
    storeBasis(basis, nc, k, true, keys.data());
    CHECK(keys[0].basicMask == (2u << 2));
    CHECK(keys[1].basicMask == 1u);
    CHECK(keys[2].basicMask == (2u << k));
    std::vector<int> back;
    for (int ci = 0; ci < nc; ++ci) appendWarmBasis(keys[std::size_t(ci)].basicMask, ci, nc, k, back);
    std::sort(back.begin(), back.end());
    CHECK(back == basis);
    std::vector<ContactKey> plain(3);
    storeBasis({0, 2}, nc, k, false, plain.data());  // frictionless basis: indices are contacts
    CHECK(plain[0].basicMask == 1u);
    CHECK(plain[1].basicMask == 0u);
    CHECK(plain[2].basicMask == 1u);
}

TEST_CASE("cache lookup ignores the mask; events are begin = now - before, end = before - now") {
    std::vector<ContactKey> entries{{2, 1, 0, 0, 7, 5}, {1, 2, 0, 0, 9, 3}};
    WarmStartCache cache;
    cache.replace(entries);
    REQUIRE(cache.entries().size() == 2);
    CHECK(cache.entries()[0].slotA == 1);
    const ContactKey* hit = cache.find({2, 1, 0, 0, 7, 0});
    REQUIRE(hit != nullptr);
    CHECK(hit->basicMask == 5u);
    CHECK(cache.find({2, 1, 0, 1, 7, 5}) == nullptr);
    const BodyId a{1, 1}, b{2, 1}, c{3, 2};
    TouchPairs now{{touchKey(b), touchKey(c)}, {touchKey(a), touchKey(b)}, {touchKey(a), touchKey(b)}};
    const TouchPairs before{{touchKey(a), touchKey(b)}, {touchKey(a), touchKey(c)}};
    std::vector<TouchEvent> begin, end;
    touchEvents(now, before, begin, end);
    CHECK(now.size() == 2);
    REQUIRE(begin.size() == 1);
    CHECK((begin[0].a == b && begin[0].b == c));
    REQUIRE(end.size() == 1);
    CHECK((end[0].a == a && end[0].b == c));
    CHECK(touchId(touchKey(c)) == c);
}

TEST_CASE("duplicate cache keys: the first in step order survives, whatever the order of the others") {
    // Three entries share one key with masks 4, 1, 2; another key sits between them in the input. Every rotation of
    // the input keeps exactly one entry per key, and it is the first of its key in the given order.
    const std::vector<ContactKey> base{{3, 1, 0, 0, 7, 4}, {1, 2, 0, 0, 9, 8}, {3, 1, 0, 0, 7, 1}, {3, 1, 0, 0, 7, 2}};
    for (std::size_t r = 0; r < base.size(); ++r) {
        std::vector<ContactKey> entries = base;
        std::rotate(entries.begin(), entries.begin() + std::ptrdiff_t(r), entries.end());
        std::uint32_t firstMask = 0;
        for (const ContactKey& e : entries)
            if (e.slotA == 3) {
                firstMask = e.basicMask;
                break;
            }
        WarmStartCache cache;
        cache.replace(entries);
        REQUIRE(cache.entries().size() == 2);
        CHECK(cache.entries()[0].slotA == 1);
        CHECK(cache.entries()[1].basicMask == firstMask);
        CHECK(cache.entries()[0] < cache.entries()[1]);
    }
}

}  // TEST_SUITE
