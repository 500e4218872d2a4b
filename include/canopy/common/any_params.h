#pragma once
// A parameter struct whose type is known at run time only: a view planner's own section,
// declared by its registry entry (nbv/view_planner.h), which the nbv settings hold without
// naming the planner. It is visited like the struct it holds (a.section(key, any, help)), by
// every archive of params.h, copied by value, and read back by type (get<P>()).

#include <memory>
#include <typeinfo>
#include <utility>

#include "canopy/common/params.h"

namespace canopy {

class AnyParams {
 public:
  AnyParams() = default;
  /// Holds `params` (a struct with a visit()).
  template <class P, class = std::enable_if_t<!std::is_same_v<std::decay_t<P>, AnyParams>>>
  explicit AnyParams(P params) : impl_(std::make_unique<Model<P>>(std::move(params))) {}
  AnyParams(const AnyParams& o) : impl_(o.impl_ ? o.impl_->clone() : nullptr) {}
  AnyParams(AnyParams&&) noexcept = default;
  AnyParams& operator=(const AnyParams& o) {
    if (this != &o) impl_ = o.impl_ ? o.impl_->clone() : nullptr;
    return *this;
  }
  AnyParams& operator=(AnyParams&&) noexcept = default;

  /// True when it holds no struct.
  bool empty() const { return !impl_; }
  /// True when it holds a P.
  template <class P>
  bool holds() const {
    return impl_ && impl_->type() == typeid(P);
  }
  /// The P it holds, or nullptr.
  template <class P>
  P* get() {
    return holds<P>() ? static_cast<P*>(impl_->data()) : nullptr;
  }
  template <class P>
  const P* get() const {
    return holds<P>() ? static_cast<const P*>(impl_->data()) : nullptr;
  }

  /// Visits the struct it holds (nothing when empty). An archive that is not one of params.h's
  /// (YamlIn, YamlOut, JsonOut, Validate, Describe, YamlDoc) does not compile: add it to Concept.
  template <class A>
  void visit(A& a) {
    if (impl_) impl_->visit(a);
  }

 private:
  struct Concept {
    virtual ~Concept() = default;
    virtual std::unique_ptr<Concept> clone() const = 0;
    virtual const std::type_info& type() const = 0;
    virtual void* data() = 0;
    virtual void visit(YamlIn& a) = 0;
    virtual void visit(YamlOut& a) = 0;
    virtual void visit(JsonOut& a) = 0;
    virtual void visit(Validate& a) = 0;
    virtual void visit(Describe& a) = 0;
    virtual void visit(YamlDoc& a) = 0;
  };
  template <class P>
  struct Model final : Concept {
    explicit Model(P p) : params(std::move(p)) {}
    std::unique_ptr<Concept> clone() const override { return std::make_unique<Model>(params); }
    const std::type_info& type() const override { return typeid(P); }
    void* data() override { return &params; }
    void visit(YamlIn& a) override { params.visit(a); }
    void visit(YamlOut& a) override { params.visit(a); }
    void visit(JsonOut& a) override { params.visit(a); }
    void visit(Validate& a) override { params.visit(a); }
    void visit(Describe& a) override { params.visit(a); }
    void visit(YamlDoc& a) override { params.visit(a); }
    P params;
  };
  std::unique_ptr<Concept> impl_;
};

}  // namespace canopy
