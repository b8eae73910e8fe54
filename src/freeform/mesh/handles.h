// Typed element handles: a plain int index that cannot be mixed up between element kinds.
// An invalid handle has index -1.
#pragma once

#include <functional>

namespace freeform {

template <class Tag>
class Handle {
 public:
  constexpr Handle() = default;
  constexpr explicit Handle(int idx) : idx_(idx) {}
  constexpr int idx() const { return idx_; }
  constexpr bool is_valid() const { return idx_ >= 0; }
  constexpr auto operator<=>(const Handle&) const = default;

 private:
  int idx_ = -1;
};

using Vertex = Handle<struct VertexTag>;
using Halfedge = Handle<struct HalfedgeTag>;
using Edge = Handle<struct EdgeTag>;
using Face = Handle<struct FaceTag>;

}  // namespace freeform

template <class Tag>
struct std::hash<freeform::Handle<Tag>> {
  std::size_t operator()(freeform::Handle<Tag> h) const noexcept { return std::hash<int>()(h.idx()); }
};
