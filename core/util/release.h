// core/util/release.h: emptying a container and handing its storage back.
// Thread safety: as the container. Memory: frees the container's storage.
#pragma once

namespace pushpin::util {

// Empties `c` and frees its storage. (`c = {}` empties a std::vector but keeps its capacity:
// the braces pick operator=(initializer_list), which assigns no elements into the same storage.)
template <class Container>
void release(Container& c) {
    Container().swap(c);
}

}  // namespace pushpin::util
