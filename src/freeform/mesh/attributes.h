// Typed per-element containers (VertexData<T>, FaceData<T>, ...), indexed by handles.
// They are plain arrays sized to the element count at creation; hot loops may use raw().
#pragma once

#include "freeform/mesh/handles.h"

#include <cstddef>
#include <vector>

namespace freeform {

template <class HandleT, class T>
class ElementData {
 public:
  ElementData() = default;
  explicit ElementData(std::size_t n, const T& init = T{}) : data_(n, init) {}
  explicit ElementData(std::vector<T> values) : data_(std::move(values)) {}

  typename std::vector<T>::reference operator[](HandleT h) { return data_[static_cast<std::size_t>(h.idx())]; }
  typename std::vector<T>::const_reference operator[](HandleT h) const {
    return data_[static_cast<std::size_t>(h.idx())];
  }
  std::size_t size() const { return data_.size(); }
  void resize(std::size_t n, const T& init = T{}) { data_.resize(n, init); }
  void fill(const T& value) { std::fill(data_.begin(), data_.end(), value); }
  std::vector<T>& raw() { return data_; }
  const std::vector<T>& raw() const { return data_; }
  auto begin() { return data_.begin(); }
  auto end() { return data_.end(); }
  auto begin() const { return data_.begin(); }
  auto end() const { return data_.end(); }

 private:
  std::vector<T> data_;
};

template <class T>
using VertexData = ElementData<Vertex, T>;
template <class T>
using HalfedgeData = ElementData<Halfedge, T>;
template <class T>
using EdgeData = ElementData<Edge, T>;
template <class T>
using FaceData = ElementData<Face, T>;

}  // namespace freeform
