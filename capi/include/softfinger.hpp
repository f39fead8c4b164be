// softfinger.hpp: header-only C++17 RAII wrapper of the softfinger C API (softfinger.h).
//
// softfinger::Device owns one sf_device handle (closed by the destructor; movable, not
// copyable). Every call that fails throws softfinger::Error with the C code and its text; a
// device refusal is the same Error with code() <= SF_ERR_REFUSED_BASE. Threads: as softfinger.h
// says; latest() never waits and may be called from a servo thread while another thread calls
// the rest.
#ifndef SOFTFINGER_HPP
#define SOFTFINGER_HPP

#include "softfinger.h"

#include <array>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>

namespace softfinger {

// A failed call: the SF_ERR_* code and sf_strerror's text.
class Error : public std::runtime_error {
  public:
    Error(const std::string &what, int code)
        : std::runtime_error(what + ": " + sf_strerror(code)), code_(code) {}
    int code() const noexcept { return code_; }
    // True when the device refused (the code carries the device's error code).
    bool refused() const noexcept { return code_ <= SF_ERR_REFUSED_BASE; }

  private:
    int code_;
};

namespace detail {
inline int check(int rc, const char *what) {
    if (rc < 0) {
        throw Error(what, rc);
    }
    return rc;
}
} // namespace detail

using Vec3 = std::array<double, 3>;

// The local model: a shape at a pose with a material, SI units (see sf_local_model).
struct LocalModel {
    int32_t shape = SF_SHAPE_PLANE;
    double radius_m = 0.0;
    Vec3 position_m{0.0, 0.0, 0.0};
    std::array<double, 4> orientation{1.0, 0.0, 0.0, 0.0};
    double stiffness_n_per_m = 2000.0;
    double damping_n_s_per_m = 2.0;
    double mu_s = 0.8;
    double mu_k = 0.6;
    double spin_stiffness_nm_per_rad = 0.01;
    uint32_t max_age_ms = 0;
};

class Device {
  public:
    // Opens "tcp:HOST:PORT", "usb" or "usb:/dev/ttyACM0"; throws Error.
    explicit Device(const std::string &target) {
        int err = 0;
        dev_ = sf_open(target.c_str(), &err);
        if (dev_ == nullptr) {
            throw Error("open " + target, err);
        }
    }
    ~Device() { sf_close(dev_); }
    Device(const Device &) = delete;
    Device &operator=(const Device &) = delete;
    Device(Device &&o) noexcept : dev_(std::exchange(o.dev_, nullptr)), seq_(o.seq_) {}
    Device &operator=(Device &&o) noexcept {
        if (this != &o) {
            sf_close(dev_);
            dev_ = std::exchange(o.dev_, nullptr);
            seq_ = o.seq_;
        }
        return *this;
    }

    sf_info_t info() {
        sf_info_t i{};
        detail::check(sf_info(dev_, &i), "sf_info");
        return i;
    }
    // Home and wait until homed; throws on failure or timeout.
    void home(double timeout_s = 10.0) { detail::check(sf_home(dev_, timeout_s), "sf_home"); }
    void arm() { detail::check(sf_arm(dev_), "sf_arm"); }
    void disarm() { detail::check(sf_disarm(dev_), "sf_disarm"); }
    void clear() { detail::check(sf_clear(dev_), "sf_clear"); }
    void set_stream(double rate_hz) { detail::check(sf_set_stream(dev_, rate_hz), "sf_set_stream"); }

    // Sends `m` with the next sequence number (after the newest the device reported) and
    // returns that number.
    uint32_t set_local_model(const LocalModel &m) {
        if (auto s = latest()) {
            if (static_cast<int32_t>(s->model_seq - seq_) > 0) {
                seq_ = s->model_seq;
            }
        }
        sf_local_model c{};
        c.seq = seq_ + 1;
        c.shape = m.shape;
        c.radius_m = m.radius_m;
        for (int i = 0; i < 3; i++) c.position_m[i] = m.position_m[i];
        for (int i = 0; i < 4; i++) c.orientation[i] = m.orientation[i];
        c.stiffness_n_per_m = m.stiffness_n_per_m;
        c.damping_n_s_per_m = m.damping_n_s_per_m;
        c.mu_s = m.mu_s;
        c.mu_k = m.mu_k;
        c.spin_stiffness_nm_per_rad = m.spin_stiffness_nm_per_rad;
        c.max_age_ms = m.max_age_ms;
        detail::check(sf_set_local_model(dev_, &c), "sf_set_local_model");
        seq_ = c.seq;
        return seq_;
    }

    // The next sample in order, or nothing after timeout_s.
    std::optional<sf_state> next(double timeout_s) {
        sf_state s{};
        if (detail::check(sf_next_state(dev_, &s, timeout_s), "sf_next_state") == 1) {
            return s;
        }
        return std::nullopt;
    }
    // The newest sample without waiting, or nothing before the first.
    std::optional<sf_state> latest() const {
        sf_state s{};
        if (detail::check(sf_latest_state(dev_, &s), "sf_latest_state") == 1) {
            return s;
        }
        return std::nullopt;
    }

    sf_device *handle() const noexcept { return dev_; }

  private:
    sf_device *dev_ = nullptr;
    uint32_t seq_ = 0;
};

} // namespace softfinger

#endif // SOFTFINGER_HPP
