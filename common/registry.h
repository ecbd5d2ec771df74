// Implementations of one interface, registered by name (Ramulator 2.0's way): a configuration
// names one, and the registry builds it. Every name is written once, where its implementation is
// registered; the readers, the checks and the documentation take the names from here.
//
// Registration is explicit: each interface's registry is filled, on first use, by one function
// that calls every implementation file's `add_...` function. Self-registering static objects
// would be simpler to add, but an object file of a static library that nothing references is
// left out by the linker (its registrar never runs), in this tree and in the installed package.
#pragma once

#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace rtsim {

// A registered name and what it means (for error messages and `rtsim params`).
struct RegisteredName {
  std::string name;
  std::string description;
};

// "'a', 'b' or 'c'"
inline std::string quoted_names(const std::vector<RegisteredName>& names) {
  std::string s;
  for (size_t i = 0; i < names.size(); ++i)
    s += (i == 0 ? "" : i + 1 == names.size() ? " or " : ", ") + ("'" + names[i].name + "'");
  return s;
}

// `kind` names the interface in errors ("DRAM scheduler").
template <class Interface, class... Args>
class Registry {
 public:
  using Factory = std::function<std::unique_ptr<Interface>(Args...)>;

  explicit Registry(std::string kind) : kind_(std::move(kind)) {}

  // A name registered twice is a programming error.
  void add(std::string name, Factory make, std::string description) {
    if (find(name)) throw std::logic_error(kind_ + " '" + name + "' registered twice");
    names_.push_back({std::move(name), std::move(description)});
    factories_.push_back(std::move(make));
  }

  // An unknown name throws std::invalid_argument listing the registered ones.
  std::unique_ptr<Interface> make(const std::string& name, Args... args) const {
    return factories_[index(name)](std::forward<Args>(args)...);
  }
  bool has(const std::string& name) const { return find(name) != nullptr; }
  const std::vector<RegisteredName>& names() const { return names_; }

 private:
  const RegisteredName* find(const std::string& name) const {
    for (const RegisteredName& n : names_)
      if (n.name == name) return &n;
    return nullptr;
  }
  size_t index(const std::string& name) const {
    for (size_t i = 0; i < names_.size(); ++i)
      if (names_[i].name == name) return i;
    throw std::invalid_argument("unknown " + kind_ + " '" + name + "' (expected " +
                                quoted_names(names_) + ")");
  }

  std::string kind_;
  std::vector<RegisteredName> names_;
  std::vector<Factory> factories_;
};

}  // namespace rtsim
