#pragma once
// Handles handed from one module's passes to the next. Each module takes the versions it reads
// from the board by key and puts back the versions its passes wrote; the modules never copy
// one another's handle structs, and a module that needs something nobody put there, or puts a
// key of one type where another expects it under the same name, is stopped with the key named.
#include <map>
#include <string>
#include <string_view>
#include <typeindex>
#include <utility>

#include "core/result.h"
#include "graph/frame_graph.h"

namespace pbdsplat::graph {

// A typed name on the board: Key<T> finds only a Handle<T>.
template <class T>
struct Key {
    std::string_view name;
};

class Blackboard {
public:
    template <class T>
    void put(Key<T> key, Handle<T> h) {
        put_entry(key.name, std::type_index(typeid(T)), h.version);
    }
    // put() for each pair: a module hands back everything its passes wrote in one statement.
    template <class... T>
    void put_all(const std::pair<Key<T>, Handle<T>>&... entries) {
        (put(entries.first, entries.second), ...);
    }
    // The handle under `key`, or an error naming the key: absent, or put there as another type.
    template <class T>
    core::Result<Handle<T>> find(Key<T> key) const {
        uint32_t version = 0;
        if (core::Status s = lookup(key.name, std::type_index(typeid(T)), version); !s.ok()) return s.error();
        return Handle<T>{version};
    }
    // As find(), for keys the graph's assembly always puts: a missing one is a programming error.
    template <class T>
    Handle<T> get(Key<T> key) const {
        uint32_t version = 0;
        require(lookup(key.name, std::type_index(typeid(T)), version));
        return Handle<T>{version};
    }
    bool has(std::string_view name) const { return entries_.find(name) != entries_.end(); }

private:
    struct Entry {
        std::type_index type;
        uint32_t version;
    };
    void put_entry(std::string_view name, std::type_index type, uint32_t version);
    core::Status lookup(std::string_view name, std::type_index type, uint32_t& version) const;
    static void require(const core::Status& s);
    std::map<std::string, Entry, std::less<>> entries_;
};

// Imports `data` into `g` under the key's name (absent when null) and puts its handle on `board`.
template <class T>
void import_into(FrameGraph& g, Blackboard& board, Key<T> key, T* data, bool persistent = false) {
    board.put(key, g.import(std::string(key.name), data, persistent));
}

} // namespace pbdsplat::graph
