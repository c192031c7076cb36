// tests/test_body_store.cpp — generational handles and dense storage (core/body_store.h): validity, stale ids,
// LIFO reuse, packing under long random create/destroy runs against a reference model, overflow, restore().
#include <doctest/doctest.h>

#include "body_store.h"

#include <cstdint>
#include <map>
#include <string>
#include <utility>
#include <vector>

using namespace unison;

namespace {

struct Hot {
    double x = 0.0;
    bool operator==(const Hot& o) const { return x == o.x; }
};
struct Cold {
    int tag = 0;
    bool operator==(const Cold& o) const { return tag == o.tag; }
};
using Store = BodyStore<Hot, Cold>;

struct Lcg {
    std::uint64_t s;
    std::uint32_t next() {
        s = s * 6364136223846793005ULL + 1442695040888963407ULL;
        return std::uint32_t(s >> 33);
    }
};

// Every invariant from the header, checked from the public accessors only.
void checkInvariants(const Store& st) {
    const auto& slots = st.slots();
    const auto& freeList = st.freeList();
    const auto& d2s = st.denseToSlot();
    REQUIRE(int(st.hotArray().size()) == st.size());
    REQUIRE(int(st.coldArray().size()) == st.size());
    REQUIRE(int(d2s.size()) == st.size());
    REQUIRE(slots.size() <= std::size_t(st.capacity()));
    std::vector<int> inFree(slots.size(), 0);
    for (std::uint32_t s : freeList) {
        REQUIRE(s < slots.size());
        ++inFree[s];
    }
    for (std::size_t s = 0; s < slots.size(); ++s) {
        CHECK(slots[s].generation >= 1u);
        CHECK((slots[s].dense == -1) == (inFree[s] == 1));
        CHECK(inFree[s] <= 1);
        if (slots[s].dense >= 0) CHECK(d2s[std::size_t(slots[s].dense)] == s);
    }
    for (int d = 0; d < st.size(); ++d) {
        CHECK(slots[d2s[std::size_t(d)]].dense == d);
        CHECK(st.denseIndex(st.idAt(d)) == d);
    }
}

// Comparable copy of everything a store holds.
struct State {
    std::vector<BodySlot> slots;
    std::vector<std::uint32_t> freeList, d2s;
    std::vector<Hot> hot;
    std::vector<Cold> cold;
};
State stateOf(const Store& st) { return {st.slots(), st.freeList(), st.denseToSlot(), st.hotArray(), st.coldArray()}; }
bool sameState(const State& a, const State& b) {
    if (a.slots.size() != b.slots.size()) return false;
    for (std::size_t i = 0; i < a.slots.size(); ++i)
        if (a.slots[i].generation != b.slots[i].generation || a.slots[i].dense != b.slots[i].dense) return false;
    return a.freeList == b.freeList && a.d2s == b.d2s && a.hot == b.hot && a.cold == b.cold;
}

// A store after a fixed sequence of creates and destroys, with holes in its slot table.
Store sampleStore() {
    Store st(16);
    std::vector<BodyId> ids;
    for (int i = 0; i < 8; ++i) ids.push_back(st.create(Hot{double(i)}, Cold{i}));
    st.destroy(ids[2]);
    st.destroy(ids[6]);
    st.destroy(ids[0]);
    st.create(Hot{10.0}, Cold{10});
    return st;
}

}  // namespace

TEST_SUITE("body_store") {

TEST_CASE("null id, create, valid, destroy") {
    CHECK(BodyId::null().isNull());
    CHECK(BodyId{}.isNull());
    CHECK(BodyId::null() == BodyId{});
    CHECK(BodyId{1, 1} != BodyId{1, 2});
    Store st;
    CHECK(st.size() == 0);
    const BodyId a = st.create(Hot{1.5}, Cold{7});
    const BodyId b = st.create(Hot{2.5}, Cold{8});
    CHECK(a == BodyId{1, 1});
    CHECK(b == BodyId{2, 1});
    CHECK(st.valid(a));
    CHECK(st.valid(b));
    CHECK_FALSE(st.valid(BodyId::null()));
    CHECK_FALSE(st.valid(BodyId{3, 1}));  // slot never used
    CHECK(st.denseIndex(b) == 1);
    CHECK(st.hot(st.denseIndex(b)).x == 2.5);
    CHECK(st.cold(st.denseIndex(a)).tag == 7);
    CHECK(st.idAt(0) == a);
    CHECK(st.idAt(2).isNull());
    CHECK(st.idAt(-1).isNull());
    CHECK_FALSE(st.destroy(BodyId::null()));
    CHECK(st.destroy(a));
    CHECK_FALSE(st.valid(a));
    CHECK_FALSE(st.destroy(a));  // double destroy
    CHECK(st.denseIndex(a) == -1);
    // b was swapped into dense 0 and its slot followed it.
    CHECK(st.size() == 1);
    CHECK(st.denseIndex(b) == 0);
    CHECK(st.hot(0).x == 2.5);
    CHECK(st.cold(0).tag == 8);
    checkInvariants(st);
}

TEST_CASE("stale ids are rejected after their slot is reused") {
    Store st;
    const BodyId a = st.create(Hot{}, Cold{1});
    REQUIRE(st.destroy(a));
    const BodyId a2 = st.create(Hot{}, Cold{2});
    CHECK(a2.index1 == a.index1);
    CHECK(a2.generation == a.generation + 1);
    CHECK_FALSE(st.valid(a));
    CHECK(st.denseIndex(a) == -1);
    CHECK_FALSE(st.destroy(a));
    CHECK(st.valid(a2));
    CHECK(st.cold(st.denseIndex(a2)).tag == 2);
}

TEST_CASE("records and ids by handle: null for stale ids, ids() in dense order after a swap-remove") {
    Store st;
    const BodyId a = st.create(Hot{1.0}, Cold{1});
    const BodyId b = st.create(Hot{2.0}, Cold{2});
    const BodyId c = st.create(Hot{3.0}, Cold{3});
    REQUIRE(st.destroy(a));  // c moves to dense index 0
    CHECK(st.findHot(a) == nullptr);
    CHECK(st.findCold(a) == nullptr);
    CHECK(st.findHot(BodyId::null()) == nullptr);
    REQUIRE(st.findHot(c) != nullptr);
    CHECK(st.findHot(c)->x == 3.0);
    CHECK(st.findCold(b)->tag == 2);
    const std::vector<BodyId> ids = st.ids();
    REQUIRE(ids.size() == 2);
    CHECK(ids[0] == c);
    CHECK(ids[1] == b);
}

TEST_CASE("freed slots are reused last-in-first-out") {
    Store st;
    std::vector<BodyId> ids;
    for (int i = 0; i < 5; ++i) ids.push_back(st.create(Hot{}, Cold{i}));
    st.destroy(ids[1]);
    st.destroy(ids[3]);
    st.destroy(ids[0]);
    CHECK(st.freeList() == std::vector<std::uint32_t>{1, 3, 0});
    CHECK(st.create(Hot{}, Cold{}) == BodyId{1, 2});  // slot 0, freed last
    CHECK(st.create(Hot{}, Cold{}) == BodyId{4, 2});  // slot 3
    CHECK(st.create(Hot{}, Cold{}) == BodyId{2, 2});  // slot 1
    CHECK(st.create(Hot{}, Cold{}) == BodyId{6, 1});  // fresh slot 5
    checkInvariants(st);
}

TEST_CASE("random create/destroy runs stay packed and agree with a reference model") {
    for (std::uint64_t seed = 1; seed <= 4; ++seed) {
        Lcg rng{seed};
        const int cap = 64;
        Store st(cap);
        std::map<std::uint32_t, std::pair<std::uint32_t, int>> live;  // slot -> (generation, tag)
        std::vector<std::uint32_t> modelFree;                         // LIFO stack of free slots
        std::vector<std::uint32_t> modelGen;                          // generation per slot
        std::vector<BodyId> dead;
        for (int step = 0; step < 4000; ++step) {
            const std::uint32_t r = rng.next() % 100;
            // Bias towards creation early so the store also runs into its capacity.
            if (r < (step < 2000 ? 60u : 40u)) {
                const int tag = step;
                const BodyId id = st.create(Hot{double(tag)}, Cold{tag});
                if (int(live.size()) == cap) {
                    CHECK(id.isNull());
                } else {
                    BodyId expect;
                    if (!modelFree.empty()) {
                        const std::uint32_t s = modelFree.back();
                        modelFree.pop_back();
                        expect = BodyId{s + 1, ++modelGen[s]};
                    } else {
                        modelGen.push_back(1);
                        expect = BodyId{std::uint32_t(modelGen.size()), 1};
                    }
                    REQUIRE(id == expect);
                    live[id.index1 - 1] = {id.generation, tag};
                }
            } else if (r < 95 && !live.empty()) {
                auto it = live.begin();
                std::advance(it, long(rng.next() % live.size()));
                const BodyId id{it->first + 1, it->second.first};
                REQUIRE(st.destroy(id));
                modelFree.push_back(it->first);
                dead.push_back(id);
                live.erase(it);
            } else if (!dead.empty()) {
                const BodyId stale = dead[rng.next() % dead.size()];
                CHECK_FALSE(st.valid(stale));
                CHECK_FALSE(st.destroy(stale));
            }
            REQUIRE(st.size() == int(live.size()));
            CHECK(st.freeList() == modelFree);
            for (const auto& kv : live) {
                const BodyId id{kv.first + 1, kv.second.first};
                const int d = st.denseIndex(id);
                REQUIRE(d >= 0);
                CHECK(st.cold(d).tag == kv.second.second);
                CHECK(st.hot(d).x == double(kv.second.second));
                CHECK(st.idAt(d) == id);
            }
            checkInvariants(st);
        }
    }
}

TEST_CASE("overflow returns a null id instead of crashing") {
    Store st(3);
    CHECK(st.capacity() == 3);
    const BodyId a = st.create(Hot{}, Cold{});
    st.create(Hot{}, Cold{});
    st.create(Hot{}, Cold{});
    CHECK(st.create(Hot{}, Cold{}).isNull());
    CHECK(st.size() == 3);
    CHECK(st.destroy(a));
    CHECK_FALSE(st.create(Hot{}, Cold{}).isNull());
    CHECK(st.create(Hot{}, Cold{}).isNull());
    checkInvariants(st);

    Store none(0);
    CHECK(none.create(Hot{}, Cold{}).isNull());
    CHECK(none.slots().empty());
}

TEST_CASE("restore round trip") {
    Store src = sampleStore();
    checkInvariants(src);
    Store dst(16);
    CHECK(dst.restore(src.slots(), src.freeList(), src.hotArray(), src.coldArray(), src.denseToSlot()) == "");
    CHECK(sameState(stateOf(src), stateOf(dst)));
    checkInvariants(dst);
    for (int d = 0; d < src.size(); ++d) CHECK(dst.valid(src.idAt(d)));
    // Both stores continue identically: the free list order survives.
    for (int i = 0; i < 5; ++i) CHECK(src.create(Hot{}, Cold{}) == dst.create(Hot{}, Cold{}));
    CHECK(sameState(stateOf(src), stateOf(dst)));
}

TEST_CASE("restore rejects inconsistent input and leaves the store untouched") {
    const Store src = sampleStore();
    const State good = stateOf(src);
    Store dst = sampleStore();
    dst.create(Hot{99.0}, Cold{99});
    const State before = stateOf(dst);

    auto expectRejected = [&](State bad, const char* what) {
        CAPTURE(what);
        const std::string err = dst.restore(bad.slots, bad.freeList, bad.hot, bad.cold, bad.d2s);
        CHECK_FALSE(err.empty());
        CHECK(sameState(stateOf(dst), before));
    };
    State s = good;
    s.hot.pop_back();
    expectRejected(s, "hot size");
    s = good;
    s.cold.push_back(Cold{});
    expectRejected(s, "cold size");
    s = good;
    s.d2s[0] = 100;
    expectRejected(s, "denseToSlot out of range");
    s = good;
    std::swap(s.d2s[0], s.d2s[1]);
    expectRejected(s, "denseToSlot does not point back");
    s = good;
    s.slots[s.freeList[0]].generation = 0;
    expectRejected(s, "generation 0");
    s = good;
    s.freeList.pop_back();
    expectRejected(s, "free slot missing from the free list");
    s = good;
    s.freeList.back() = s.freeList.front();
    expectRejected(s, "duplicate free entry");
    s = good;
    s.freeList.push_back(s.d2s[0]);
    expectRejected(s, "live slot in the free list");
    s = good;
    s.freeList[0] = 1000;
    expectRejected(s, "free entry out of range");
    s = good;
    s.slots[s.freeList[0]].dense = -5;
    expectRejected(s, "negative dense index other than -1");
    s = good;
    s.slots.resize(17, BodySlot{1, -1});
    for (std::uint32_t k = std::uint32_t(good.slots.size()); k < 17; ++k) s.freeList.push_back(k);
    expectRejected(s, "more slots than capacity");

    // The same store still accepts a valid state afterwards.
    CHECK(dst.restore(good.slots, good.freeList, good.hot, good.cold, good.d2s) == "");
    CHECK(sameState(stateOf(dst), good));
}

}  // TEST_SUITE
