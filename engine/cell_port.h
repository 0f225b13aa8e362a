// Memory port of one emulated SPE (software thread): vertices and half-edges are read through
// the SPE's non-coherent software cache, written with DMA puts straight to main memory, and the
// status words change only through the atomic unit. Knows the mesh layout; cellsim does not.
#pragma once

#include <atomic>
#include <cstring>
#include <limits>

#include "cellsim/cellsim.h"
#include "engine/mesh.h"
#include "engine/ring.h"

namespace femsimp {

class CellPort {
 public:
  CellPort(cellsim::SpeContext& spe, Mesh& mesh)
      : spe_(spe),
        v_(mesh.vertices()),
        h_(mesh.halfedges()),
        s_(reinterpret_cast<uint32_t*>(mesh.status())),
        a_(mesh.face_attrs()),
        q_(mesh.quadrics()) {
    static_assert(sizeof(std::atomic<uint32_t>) == sizeof(uint32_t));
  }

  void BeginCandidate() { logged_ = 0; }

  VertexQ ReadVertex(uint32_t v) { return Read<VertexQ>(&v_[v], Poison(&v_[v])); }
  HalfEdgeQ ReadHalfEdge(uint32_t h) { return Read<HalfEdgeQ>(&h_[h], Poison(&h_[h])); }
  VertexQ ReadVertexFresh(uint32_t v) {
    spe_.cache().Dirty(cellsim::Ea(&v_[v]));
    return ReadVertex(v);
  }
  HalfEdgeQ ReadHalfEdgeFresh(uint32_t h) {
    spe_.cache().Dirty(cellsim::Ea(&h_[h]));
    return ReadHalfEdge(h);
  }

  // A write puts the whole quadword. The other three words come from this SPE's copy, which
  // the kernel has validated (or re-read fresh) under the locks, so they are current; and no
  // other SPE writes the quadword meanwhile (kernel.h).
  void WriteTarget(uint32_t h, uint32_t v) { WriteWord(&h_[h], &HalfEdgeQ::target, v); }
  void WriteTwin(uint32_t h, uint32_t t) { WriteWord(&h_[h], &HalfEdgeQ::twin, t); }
  void WriteFlags(uint32_t h, uint32_t f) { WriteWord(&h_[h], &HalfEdgeQ::flags, f); }
  void WriteOut(uint32_t v, uint32_t h) { WriteWord(&v_[v], &VertexQ::out, h); }
  void WritePosition(uint32_t v, const Vec3& p) {
    VertexQ q = Read<VertexQ>(&v_[v], Poison(&v_[v]));
    q.x = p.x;
    q.y = p.y;
    q.z = p.z;
    Put(&v_[v], q);
  }

  uint32_t LoadStatus(uint32_t v) { return Check(spe_.atomic().Load(&s_[v]), uint32_t{kRemoved}); }
  bool CasStatus(uint32_t v, uint32_t expected, uint32_t desired) {
    return Check(spe_.atomic().CompareAndSwap(&s_[v], expected, desired), false);
  }
  void StoreStatus(uint32_t v, uint32_t value) {
    // The DMA puts of an update must be complete before its status words are released.
    if (puts_in_flight_) {
      (void)spe_.dma().WaitTagMask(1u << kPutTag);
      puts_in_flight_ = 0;
    }
    Check(spe_.atomic().PutLluc(&s_[v], value));
  }

  // Stale data detected: dirty the lines this candidate has read, so they are fetched again.
  bool Refresh() {
    ++spe_.counters().stale_detections;
    if (logged_ > kLogSize) {
      spe_.cache().InvalidateAll();
    } else {
      for (int i = 0; i < logged_; ++i) spe_.cache().Dirty(log_[i]);
    }
    logged_ = 0;
    return reread_on_stale_;
  }
  void set_reread_on_stale(bool on) { reread_on_stale_ = on; }

  void ChargeCompute(uint32_t cycles) { spe_.AddComputeCycles(cycles); }

  // Side quadwords bypass the software cache: they are read only under the locks that guard
  // them, so a DMA get straight from main memory is current.
  FaceAttrQ ReadFaceAttr(uint32_t f) {
    // A failed read gives an infinite bound and the widest box: the collapse is refused.
    constexpr int16_t lo = std::numeric_limits<int16_t>::min();
    constexpr int16_t hi = std::numeric_limits<int16_t>::max();
    return Get(&a_[f], FaceAttrQ{1e30f, {0, 0, 0}, {lo, lo, lo}, {hi, hi, hi}, 0});
  }
  void WriteFaceAttr(uint32_t f, const FaceAttrQ& q) { Put(&a_[f], q); }
  QuadricQ ReadQuadric(uint32_t v) { return Get(&q_[v], QuadricQ{}); }
  void WriteQuadric(uint32_t v, const QuadricQ& q) { Put(&q_[v], q); }

 private:
  static constexpr unsigned kPutTag = 1;
  static constexpr unsigned kGetTag = 2;
  static constexpr int kLogSize = 256;
  static constexpr int kPutBuffers = 32;

  template <class Q>
  Q Read(const Q* p, Q poison) {
    const uint64_t ea = cellsim::Ea(p);
    if (logged_ < kLogSize) log_[logged_] = ea;
    ++logged_;
    absl::StatusOr<Q> q = spe_.cache().ReadValue<Q>(ea);
    if (!q.ok()) {
      spe_.ReportError(q.status());
      return poison;  // fails every consistency check, so the candidate is given up
    }
    return *q;
  }

  // Puts the quadword at p with one word changed.
  template <class Q>
  void WriteWord(Q* p, uint32_t Q::*word, uint32_t value) {
    Q q = Read<Q>(p, Poison(p));
    q.*word = value;
    Put(p, q);
  }
  static VertexQ Poison(const VertexQ*) { return VertexQ{0, 0, 0, kNone}; }
  static HalfEdgeQ Poison(const HalfEdgeQ*) { return HalfEdgeQ{kNone, kNone, 0, kFaceRemoved}; }

  template <class Q>
  Q Get(const Q* p, Q poison) {
    static_assert(sizeof(Q) <= sizeof(get_buffer_));
    absl::StatusOr<uint64_t> issued =
        spe_.dma().Get(get_buffer_, cellsim::Ea(p), sizeof(Q), kGetTag);
    if (issued.ok()) {
      if (absl::Status s = spe_.dma().WaitTagMask(1u << kGetTag); s.ok()) {
        Q q;
        std::memcpy(&q, get_buffer_, sizeof q);
        return q;
      } else {
        spe_.ReportError(s);
      }
    } else {
      spe_.ReportError(issued.status());
    }
    return poison;
  }

  template <class Q>
  void Put(Q* p, const Q& q) {
    static_assert(sizeof(Q) <= sizeof(put_buffers_[0]));
    // DMA sources must live in the local store: the buffers are members of this port, which
    // sits on the software thread's stack, itself allocated from the local store.
    if (puts_in_flight_ == kPutBuffers) {
      (void)spe_.dma().WaitTagMask(1u << kPutTag);
      puts_in_flight_ = 0;
    }
    void* buffer = &put_buffers_[puts_in_flight_++];
    std::memcpy(buffer, &q, sizeof q);
    absl::StatusOr<uint64_t> done = spe_.dma().Put(buffer, cellsim::Ea(p), sizeof q, kPutTag);
    if (!done.ok()) spe_.ReportError(done.status());
  }

  template <class T>
  T Check(absl::StatusOr<T> r, T fallback) {
    if (r.ok()) return *r;
    spe_.ReportError(r.status());
    return fallback;
  }
  void Check(absl::Status s) {
    if (!s.ok()) spe_.ReportError(s);
  }

  cellsim::SpeContext& spe_;
  VertexQ* v_;
  HalfEdgeQ* h_;
  uint32_t* s_;
  bool reread_on_stale_ = true;
  int logged_ = 0;
  uint64_t log_[kLogSize];
  int puts_in_flight_ = 0;
  FaceAttrQ* a_;
  QuadricQ* q_;
  struct alignas(16) PutBuffer {
    std::byte bytes[sizeof(QuadricQ)];
  };
  PutBuffer put_buffers_[kPutBuffers];
  alignas(16) std::byte get_buffer_[sizeof(QuadricQ)];
};

}  // namespace femsimp
