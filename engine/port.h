// The memory "port" the removal kernel is written against. Each back end provides one:
// the native port touches the shared arrays directly, the cell port goes through an SPE's
// software cache (reads), DMA puts (writes) and atomic unit (status words).
//
//   VertexQ ReadVertex(uint32_t v);
//   HalfEdgeQ ReadHalfEdge(uint32_t h);
//   HalfEdgeQ ReadHalfEdgeFresh(uint32_t h);   // bypasses any cached copy (and ReadVertexFresh)
//   void WriteTarget(uint32_t h, uint32_t v);  // and WriteTwin, WriteFlags, WriteOut
//   void WritePosition(uint32_t v, const Vec3& p);  // a full-edge collapse's new vertex
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
#include "engine/ring.h"

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
  // is defined behaviour (plain moves on x86). Positions change only in a full-edge collapse
  // (option placement), under the locks of the vertex and its ring; a kernel that may see them
  // move re-reads them once it holds its locks.
  VertexQ ReadVertex(uint32_t v) const {
    VertexQ& q = v_[v];
    return {Load(q.x), Load(q.y), Load(q.z), Load(q.out)};
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
  void WritePosition(uint32_t v, const Vec3& p) {
    Store(v_[v].x, p.x);
    Store(v_[v].y, p.y);
    Store(v_[v].z, p.z);
  }
  uint32_t LoadStatus(uint32_t v) const { return s_[v].load(std::memory_order_acquire); }
  bool CasStatus(uint32_t v, uint32_t expected, uint32_t desired) {
    return s_[v].compare_exchange_strong(expected, desired, std::memory_order_acq_rel,
                                         std::memory_order_acquire);
  }
  void StoreStatus(uint32_t v, uint32_t value) { s_[v].store(value, std::memory_order_release); }
  // Cache warming for a coming candidate, in two stages some candidates apart: its quadword and
  // status word, then (once the quadword has arrived) the face of its first out half-edge and
  // that face's side quadword. The ring walk is a chain of dependent loads; started early, its
  // first links overlap the work on the candidates before it. Hints only: a stale `out` just
  // warms the wrong lines.
  void PrefetchVertex(uint32_t v) const {
    __builtin_prefetch(&v_[v]);
    __builtin_prefetch(&s_[v]);
  }
  void PrefetchFan(uint32_t v) const {
    const uint32_t h = Load(v_[v].out);
    if (h == kNone) return;
    const HalfEdgeQ* face = &h_[h - h % 3];
    __builtin_prefetch(face);
    __builtin_prefetch(face + 2);
    if (a_ != nullptr) __builtin_prefetch(&a_[h / 3]);
  }
  void BeginCandidate() {}
  bool Refresh() { return false; }
  void ChargeCompute(uint32_t) {}
  FaceAttrQ ReadFaceAttr(uint32_t f) const { return a_[f]; }
  void WriteFaceAttr(uint32_t f, const FaceAttrQ& q) { a_[f] = q; }
  QuadricQ ReadQuadric(uint32_t v) const { return q_[v]; }
  void WriteQuadric(uint32_t v, const QuadricQ& q) { q_[v] = q; }

 private:
  template <class W>
  static W Load(W& word) {
    return std::atomic_ref<W>(word).load(std::memory_order_relaxed);
  }
  template <class W>
  static void Store(W& word, W value) {
    std::atomic_ref<W>(word).store(value, std::memory_order_relaxed);
  }

  VertexQ* v_;
  HalfEdgeQ* h_;
  std::atomic<uint32_t>* s_;
  FaceAttrQ* a_;
  QuadricQ* q_;
};

}  // namespace femsimp
