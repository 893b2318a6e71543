#pragma once
// Which point a sweep process runs next. Alone, the points in order; under `mpirun -np N` (a
// build with MPI, started by mpirun), a dynamic queue: rank 0 hands out the next point to
// whichever rank asks, so the slowest point holds up only its own rank, and it runs points
// itself while answering (`serve`, called while its point's process runs). A rank that dies loses
// only its point in flight: that point's state file says `running`, and a rerun resumes it.
#include <cstddef>
#include <memory>
#include <optional>

namespace mrjam {

class PointQueue {
public:
    virtual ~PointQueue() = default;
    // How many points there are to hand out (every process holds the same list).
    void set_count(std::size_t count) { count_ = count; }
    // Every process waits here for the others (before the list is read, and once it is).
    virtual void synchronise() {}
    // The next point, as an index into the list every process holds; none when all are handed out.
    virtual std::optional<std::size_t> next() = 0;
    // Answers the other processes' requests; cheap when there are none.
    virtual void serve() {}
    // This process takes no more points (done or interrupted): the leader waits here until every
    // other process has said so too.
    virtual void finish() {}
    // The process that writes the sweep's registry and table.
    virtual bool leader() const { return true; }
    // Its number and the number of processes, for progress lines.
    virtual int rank() const { return 0; }
    virtual int size() const { return 1; }

protected:
    std::size_t count_ = 0;
};

// The queue: an MPI queue when this process was started by mpirun in a build
// with MPI, the points in order otherwise. Returns the one queue of the process (MPI is
// initialised once and finalised at exit).
std::unique_ptr<PointQueue> make_point_queue();

// The points in order, in this process alone (a mode that sweeps inside itself).
std::unique_ptr<PointQueue> make_local_queue();

// Whether this build can run a sweep under mpirun (the report of `mrjam sweep --help` says so).
bool sweep_has_mpi();

}  // namespace mrjam
