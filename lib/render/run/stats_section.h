#pragma once
// A section of a run's statistics that one integrator or gather keeps (render/photon_map/
// photon_map_stats.h, the beam gathers' stats): RunStats holds the sections without knowing their
// types, copies them with the run and has each write its own keys into the run record.
#include <memory>
#include <vector>

namespace vpm {

class RunRecord;

class StatsSection {
public:
    virtual ~StatsSection() = default;
    virtual std::unique_ptr<StatsSection> clone() const = 0;
    // Writes the section's keys into `record` (docs/rendering.md lists them).
    virtual void write(RunRecord& record) const = 0;
};

// The clone every section needs, for a section type T deriving from StatsSectionOf<T>.
template <class T>
class StatsSectionOf : public StatsSection {
public:
    std::unique_ptr<StatsSection> clone() const override {
        return std::make_unique<T>(static_cast<const T&>(*this));
    }
};

// The sections of one run, at most one per type, copied with the run (each by its clone).
class StatsSections {
public:
    StatsSections() = default;
    StatsSections(const StatsSections& other) {
        for (const auto& s : other.list_) list_.push_back(s->clone());
    }
    StatsSections& operator=(const StatsSections& other) {
        if (this != &other) *this = StatsSections(other);
        return *this;
    }
    StatsSections(StatsSections&&) = default;
    StatsSections& operator=(StatsSections&&) = default;

    // The section of type T, or nullptr when the run kept none.
    template <class T>
    const T* find() const {
        for (const auto& s : list_)
            if (const auto* t = dynamic_cast<const T*>(s.get())) return t;
        return nullptr;
    }
    // The section of type T, added empty when the run has none yet.
    template <class T>
    T& get() {
        for (auto& s : list_)
            if (auto* t = dynamic_cast<T*>(s.get())) return *t;
        list_.push_back(std::make_unique<T>());
        return static_cast<T&>(*list_.back());
    }
    void write(RunRecord& record) const {
        for (const auto& s : list_) s->write(record);
    }

private:
    std::vector<std::unique_ptr<StatsSection>> list_;
};

}  // namespace vpm
