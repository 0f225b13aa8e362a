// The memory "port" the removal kernel is written against. Each back end provides one:
// the native port touches the shared arrays directly, the cell port goes through an SPE's
// software cache (reads), DMA puts (writes) and atomic unit (status words).
//
//   VertexQ ReadVertex(uint32_t v);
//   HalfEdgeQ ReadHalfEdge(uint32_t h);
//   HalfEdgeQ ReadHalfEdgeFresh(uint32_t h);   // bypasses any cached copy (and ReadVertexFresh)
//   void WriteTarget(uint32_t h, uint32_t v);  // and WriteTwin, WriteFlags, WriteOut
//   uint32_t LoadStatus(uint32_t v);
//   bool CasStatus(uint32_t v, uint32_t expected, uint32_t desired);  // acquire
//   void StoreStatus(uint32_t v, uint32_t value);                       // release
//   void BeginCandidate();     // a new candidate starts (the cell port logs what it reads)
//   bool Refresh();            // drop cached mesh data after a stale read; false: cannot help
//   void ChargeCompute(uint32_t cycles);  // cycle model of the arithmetic (no-op natively)
//   FaceAttrQ ReadFaceAttr(uint32_t f);   // side quadwords, read current (the kernel holds the
//   void WriteFaceAttr(uint32_t f, const FaceAttrQ&);  // locks that guard them)
//   QuadricQ ReadQuadric(uint32_t v);     // and WriteQuadric
#pragma once

#include <atomic>

#include "engine/mesh.h"

namespace femsimp {

// Plain shared-memory port: the coherent caches of the host make every read current once the
// reader holds the locks that guard the data (see kernel.h for which locks guard what).
class NativePort {
 public:
  explicit NativePort(Mesh& mesh)
      : v_(mesh.vertices()),
        h_(mesh.halfedges()),
        s_(mesh.status()),
        a_(mesh.face_attrs()),
        q_(mesh.quadrics()) {}

  // A ring is gathered before its neighbours are locked, so a word it reads (a link edge's
  // twin or flags) may be rewritten meanwhile by a context that locked both ends of that edge;
  // the kernel never uses such a word unvalidated. Words are relaxed atomics so that such a read
  // is defined behaviour (plain moves on x86); positions are never written during a pass.
  VertexQ ReadVertex(uint32_t v) const {
    const VertexQ& q = v_[v];
    return {q.x, q.y, q.z, Load(v_[v].out)};
  }
  HalfEdgeQ ReadHalfEdge(uint32_t h) const {
    HalfEdgeQ& q = h_[h];
    return {Load(q.target), Load(q.twin), Load(q.group), Load(q.flags)};
  }
  HalfEdgeQ ReadHalfEdgeFresh(uint32_t h) const { return ReadHalfEdge(h); }
  VertexQ ReadVertexFresh(uint32_t v) const { return ReadVertex(v); }
  void WriteTarget(uint32_t h, uint32_t v) { Store(h_[h].target, v); }
  void WriteTwin(uint32_t h, uint32_t t) { Store(h_[h].twin, t); }
  void WriteFlags(uint32_t h, uint32_t f) { Store(h_[h].flags, f); }
  void WriteOut(uint32_t v, uint32_t h) { Store(v_[v].out, h); }
  uint32_t LoadStatus(uint32_t v) const { return s_[v].load(std::memory_order_acquire); }
  bool CasStatus(uint32_t v, uint32_t expected, uint32_t desired) {
    return s_[v].compare_exchange_strong(expected, desired, std::memory_order_acq_rel,
                                         std::memory_order_acquire);
  }
  void StoreStatus(uint32_t v, uint32_t value) { s_[v].store(value, std::memory_order_release); }
  void BeginCandidate() {}
  bool Refresh() { return false; }
  void ChargeCompute(uint32_t) {}
  FaceAttrQ ReadFaceAttr(uint32_t f) const { return a_[f]; }
  void WriteFaceAttr(uint32_t f, const FaceAttrQ& q) { a_[f] = q; }
  QuadricQ ReadQuadric(uint32_t v) const { return q_[v]; }
  void WriteQuadric(uint32_t v, const QuadricQ& q) { q_[v] = q; }

 private:
  static uint32_t Load(uint32_t& word) {
    return std::atomic_ref<uint32_t>(word).load(std::memory_order_relaxed);
  }
  static void Store(uint32_t& word, uint32_t value) {
    std::atomic_ref<uint32_t>(word).store(value, std::memory_order_relaxed);
  }

  VertexQ* v_;
  HalfEdgeQ* h_;
  std::atomic<uint32_t>* s_;
  FaceAttrQ* a_;
  QuadricQ* q_;
};

}  // namespace femsimp
