// Type-erased, immutable, shared values passed between nodes (MediaPipe's packet idea): fan-out
// copies a pointer, never the data. Each C++ type that travels on a port is bound to the type name
// ports declare with GSLIFT_PORT_TYPE(T, "Name") (base/port_type.hpp).
#pragma once

#include <memory>
#include <stdexcept>
#include <string>
#include <typeindex>

#include "base/port_type.hpp"

namespace gslift {

class Value {
 public:
  Value() = default;
  template <class T>
  static Value of(std::shared_ptr<const T> p) {
    Value v;
    v.type_name_ = PortTypeName<T>::value;
    v.type_ = std::type_index(typeid(T));
    v.ptr_ = std::move(p);
    return v;
  }
  template <class T>
  static Value make(T value) {
    return of<T>(std::make_shared<const T>(std::move(value)));
  }

  bool empty() const { return ptr_ == nullptr; }
  const std::string& type_name() const { return type_name_; }

  template <class T>
  std::shared_ptr<const T> get() const {
    if (!ptr_ || type_ != std::type_index(typeid(T)))
      throw std::logic_error("value of type '" + type_name_ + "' read as '" +
                             PortTypeName<T>::value + "'");
    return std::static_pointer_cast<const T>(ptr_);
  }

 private:
  std::string type_name_;
  std::type_index type_ = std::type_index(typeid(void));
  std::shared_ptr<const void> ptr_;
};

}  // namespace gslift
