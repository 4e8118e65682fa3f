// The name under which a C++ type travels on node ports. A type declares it beside its definition
// with GSLIFT_PORT_TYPE(T, "Name"); this header depends on nothing, so the port types of
// nodes/scene/ declare their names without linking the runtime, whose Value (runtime/value.hpp)
// reads them.
#pragma once

namespace gslift {

template <class T>
struct PortTypeName;  // specialised by GSLIFT_PORT_TYPE

#define GSLIFT_PORT_TYPE(T, NAME)              \
  template <>                                  \
  struct PortTypeName<T> {                     \
    static constexpr const char* value = NAME; \
  }

}  // namespace gslift
