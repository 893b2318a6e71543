#include "sweep/point_queue.hpp"

#include <chrono>
#include <cstdlib>
#include <thread>

#ifdef MRJAM_WITH_MPI
#include <mpi.h>
#endif

#include "run/interrupt.hpp"

namespace mrjam {
namespace {

class LocalQueue : public PointQueue {
public:
    std::optional<std::size_t> next() override {
        if (cursor_ >= count_) return std::nullopt;
        return cursor_++;
    }

private:
    std::size_t cursor_ = 0;
};

#ifdef MRJAM_WITH_MPI
constexpr int kTagRequest = 1, kTagReply = 2, kTagDone = 3;

// Rank 0 hands out indices; -1 says there are none left (or the sweep was interrupted).
class MpiQueue : public PointQueue {
public:
    MpiQueue() {
        MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
        MPI_Comm_size(MPI_COMM_WORLD, &size_);
    }
    ~MpiQueue() override { MPI_Finalize(); }

    std::optional<std::size_t> next() override {
        if (rank_ == 0) {
            serve();
            return take();
        }
        long index = -1;
        int request = 0;
        MPI_Send(&request, 1, MPI_INT, 0, kTagRequest, MPI_COMM_WORLD);
        MPI_Recv(&index, 1, MPI_LONG, 0, kTagReply, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
        if (index < 0) return std::nullopt;
        return static_cast<std::size_t>(index);
    }

    void serve() override {
        if (rank_ != 0) return;
        int pending = 0;
        MPI_Status status;
        for (;;) {
            MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &pending, &status);
            if (!pending) return;
            int message = 0;
            MPI_Recv(&message, 1, MPI_INT, status.MPI_SOURCE, status.MPI_TAG, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
            if (status.MPI_TAG == kTagDone) {
                ++finished_;
                continue;
            }
            const std::optional<std::size_t> t = take();
            const long index = t ? static_cast<long>(*t) : -1;
            MPI_Send(&index, 1, MPI_LONG, status.MPI_SOURCE, kTagReply, MPI_COMM_WORLD);
        }
    }

    void finish() override {
        if (rank_ != 0) {
            int message = 0;
            MPI_Send(&message, 1, MPI_INT, 0, kTagDone, MPI_COMM_WORLD);
            return;
        }
        while (finished_ < size_ - 1) {
            serve();
            std::this_thread::sleep_for(std::chrono::milliseconds(20));
        }
    }

    void synchronise() override { MPI_Barrier(MPI_COMM_WORLD); }
    bool leader() const override { return rank_ == 0; }
    int rank() const override { return rank_; }
    int size() const override { return size_; }

private:
    std::optional<std::size_t> take() {
        if (cursor_ >= count_ || interrupt_requested()) return std::nullopt;
        return cursor_++;
    }

    std::size_t cursor_ = 0;
    int rank_ = 0, size_ = 1, finished_ = 0;
};

// Started by mpirun (Open MPI or MPICH set these): a plain run never initialises MPI.
bool started_by_mpirun() { return std::getenv("OMPI_COMM_WORLD_SIZE") || std::getenv("PMI_SIZE"); }
#endif

}  // namespace

bool sweep_has_mpi() {
#ifdef MRJAM_WITH_MPI
    return true;
#else
    return false;
#endif
}

std::unique_ptr<PointQueue> make_local_queue() { return std::make_unique<LocalQueue>(); }

std::unique_ptr<PointQueue> make_point_queue() {
#ifdef MRJAM_WITH_MPI
    if (started_by_mpirun()) {
        int initialised = 0;
        MPI_Initialized(&initialised);
        if (!initialised) MPI_Init(nullptr, nullptr);
        return std::make_unique<MpiQueue>();
    }
#endif
    return std::make_unique<LocalQueue>();
}

}  // namespace mrjam
