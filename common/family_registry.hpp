/// @file family_registry.hpp
/// The one table of an algorithm family (Wahba solvers, star identifiers, centroiders): names,
/// help text and factories, so that adding a member is one file plus one line.
///
/// Two ways in, because the project's libraries are static:
///  - A member that lives in a library: one line in the family's registry table (the
///    X-macro list in the family's registry .cpp), which both declares the factory the
///    member's file defines and lists it. A self-registering static object in a library file
///    would be dropped by the linker whenever nothing else references that object file: the
///    table references every factory, so no member can silently vanish.
///  - A member compiled straight into an executable (a test, an experiment, a plugin): one
///    line at namespace scope,
///      ST_REGISTER_FAMILY_MEMBER(st::WahbaSolver, "name", "one-line help", &makeMySolver);
///    It registers during static initialisation, before main(). Object files of an
///    executable are always linked, so this is safe there (and only there).
///    GoogleTest evaluates `ValuesIn(Family::names())` inside main(), so a family's shared
///    test suite sees such a member without being edited.
///
/// A family class provides `using Make = <function type>`, `using Factory = Make*` and
/// `static void registerMember(const std::string& name, const std::string& help, Factory)`.
/// Registration is not thread-safe: register before any concurrent use (static init is).
#pragma once
#include <string>
#include <utility>
#include <vector>

#include "common/check.hpp"

namespace st {

template <class Factory>
struct FamilyMember {
  std::string name;
  std::string help;  ///< one line
  Factory make;
};

template <class Factory>
class FamilyRegistry {
 public:
  using Member = FamilyMember<Factory>;

  /// `family` names the family in messages ("Wahba solver"); `members` in table order (the
  /// first is listed first in help and CLI choices).
  FamilyRegistry(std::string family, std::vector<Member> members) : family_(std::move(family)) {
    for (Member& m : members) add(std::move(m));
  }

  /// A duplicate or empty name, or a null factory, is a bug of the registering code.
  void add(Member m) {
    ST_ASSERT(!m.name.empty() && m.make != nullptr);
    ST_ASSERT(find(m.name) == nullptr);
    members_.push_back(std::move(m));
  }

  /// nullptr for an unknown name.
  const Member* find(const std::string& name) const {
    for (const Member& m : members_)
      if (m.name == name) return &m;
    return nullptr;
  }

  const std::vector<Member>& members() const { return members_; }

  /// The member `name` made with `args`, or nullptr and *error = unknownMessage(name).
  template <class... Args>
  auto create(const std::string& name, std::string* error, Args&&... args) const
      -> decltype(std::declval<Factory>()(std::forward<Args>(args)...)) {
    if (const Member* m = find(name)) return m->make(std::forward<Args>(args)...);
    if (error) *error = unknownMessage(name);
    return nullptr;
  }

  std::vector<std::string> names() const {
    std::vector<std::string> out;
    out.reserve(members_.size());
    for (const Member& m : members_) out.push_back(m.name);
    return out;
  }

  /// "unknown <family> '<name>'; valid: a b c" (for InputError or a create() error).
  std::string unknownMessage(const std::string& name) const {
    std::string s = "unknown " + family_ + " '" + name + "'; valid:";
    for (const Member& m : members_) s += " " + m.name;
    return s;
  }

 private:
  std::string family_;
  std::vector<Member> members_;
};

/// Registers one member of `Family` from its constructor (see the file comment).
template <class Family>
struct FamilyRegistrar {
  FamilyRegistrar(const char* name, const char* help, typename Family::Factory make) {
    Family::registerMember(name, help, make);
  }
};

}  // namespace st

#define ST_FAMILY_CONCAT_IMPL_(a, b) a##b
#define ST_FAMILY_CONCAT_(a, b) ST_FAMILY_CONCAT_IMPL_(a, b)
/// One line registers a member compiled into an executable (not into a static library).
#define ST_REGISTER_FAMILY_MEMBER(Family, name, help, factory)                        \
  static const ::st::FamilyRegistrar<Family> ST_FAMILY_CONCAT_(st_family_member_, \
                                                               __COUNTER__)(name, help, factory)
/// The registry table's line of a library member, expanded by the family's X-macro list:
/// X(name, factory, help) -> {name, help, &factory}.
#define ST_FAMILY_TABLE_ENTRY(name, factory, help) {name, help, &factory},
