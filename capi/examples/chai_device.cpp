// chai_device.cpp: the shape of a CHAI3D device class over softfinger.hpp, and its test against
// the virtual device.
//
//   c++ -std=c++17 -O2 -I capi/include capi/examples/chai_device.cpp -L target/release
//       -lsoftfinger -o chai_device && ./chai_device tcp:127.0.0.1:7700
//
// cSoftfingerDevice has the four methods of CHAI3D's cGenericHapticDevice that matter: open(),
// calibrate() (= home), getPosition() and setForce(). Porting it into CHAI3D is copying their
// bodies into a cGenericHapticDevice subclass (cVector3d below stands in for CHAI3D's).
//
// setForce goes through the local model: the device renders its own 10 kHz spring, so the
// application's force becomes the plane that gives it ("intermediate representation"): normal
// along the force, placed so the device's spring k * penetration equals |force| at the
// position the force was computed for. A static wall in the application's world therefore
// becomes the same plane on the device at every update, and its stiffness is rendered at the
// device's rate, not the application's.
//
// The test: a wall 2 mm into the fingertip, 1 s of a 1 kHz servo loop (getPosition, the wall's
// force, setForce), then the device's streamed normal force against the spring on the streamed
// penetration (same bound as press.c, derived there), and bad arguments as exceptions.
#include "softfinger.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <thread>
#include <vector>

// Stand-in for CHAI3D's cVector3d.
struct cVector3d {
    double x = 0.0, y = 0.0, z = 0.0;
    double length() const { return std::sqrt(x * x + y * y + z * z); }
};

class cSoftfingerDevice {
  public:
    explicit cSoftfingerDevice(std::string target, double stiffness_n_per_m = 200.0)
        : target_(std::move(target)), k_(stiffness_n_per_m) {}

    // CHAI3D: open() connects; false on failure.
    bool open() {
        try {
            dev_.emplace(target_);
            info_ = dev_->info();
            dev_->set_stream(1000.0);
            return true;
        } catch (const softfinger::Error &e) {
            std::fprintf(stderr, "cSoftfingerDevice::open: %s\n", e.what());
            return false;
        }
    }
    bool close() {
        dev_.reset();
        return true;
    }
    // CHAI3D: calibrate() = home, then arm (force ramps in over 0.5 s).
    bool calibrate(bool = false) {
        try {
            dev_->home(30.0);
            dev_->arm();
            return true;
        } catch (const softfinger::Error &e) {
            std::fprintf(stderr, "cSoftfingerDevice::calibrate: %s\n", e.what());
            return false;
        }
    }
    // CHAI3D: getPosition() of the end effector (the fingertip centre), m, never waits. The
    // position is kept: the application computes its next force for it.
    bool getPosition(cVector3d &p) {
        auto s = dev_->latest();
        if (!s) return false;
        p = {s->position_m[0], s->position_m[1], s->position_m[2]};
        last_position_ = p;
        have_position_ = true;
        return true;
    }
    // CHAI3D: setForce(); the force becomes the plane that renders it (see the top), placed for
    // the position of the last getPosition() (the one the force was computed for: a newer
    // sample would move the plane by the probe's motion in between).
    bool setForce(const cVector3d &f) {
        if (!have_position_) return false;
        const cVector3d p = last_position_;
        const double r = info_.fingertip_radius_m, mag = f.length();
        softfinger::LocalModel m;
        m.stiffness_n_per_m = k_;
        m.damping_n_s_per_m = 2.0;
        m.max_age_ms = 100; // the force fades if the application stops updating
        cVector3d n = mag > 0.0 ? cVector3d{f.x / mag, f.y / mag, f.z / mag} : last_normal_;
        // No force: keep the plane if it does not touch here, else move it 1 cm clear.
        double depth = mag > 0.0 ? mag / k_ : -0.01;
        if (mag == 0.0 && have_plane_ && !touches(p)) return true;
        // Plane through p - n * (r - depth), normal n, its origin the foot of the normal from
        // the base origin (so a wall's plane is the same at every update); the quaternion
        // turns +z onto n.
        double d = r - depth;
        double h = (p.x - n.x * d) * n.x + (p.y - n.y * d) * n.y + (p.z - n.z * d) * n.z;
        m.position_m = {n.x * h, n.y * h, n.z * h};
        double w = 1.0 + n.z;
        if (w < 1e-9) {
            m.orientation = {0.0, 1.0, 0.0, 0.0}; // n = -z: half a turn about x
        } else {
            double s = std::sqrt(2.0 * w);
            m.orientation = {s / 2.0, -n.y / s, n.x / s, 0.0};
        }
        try {
            dev_->set_local_model(m);
        } catch (const softfinger::Error &e) {
            std::fprintf(stderr, "cSoftfingerDevice::setForce: %s\n", e.what());
            return false;
        }
        plane_ = m;
        have_plane_ = true;
        last_normal_ = n;
        return true;
    }

    softfinger::Device &device() { return *dev_; }
    const sf_info_t &info() const { return info_; }

  private:
    bool touches(const cVector3d &p) const {
        const auto &o = plane_.position_m;
        double h = (p.x - o[0]) * last_normal_.x + (p.y - o[1]) * last_normal_.y +
                   (p.z - o[2]) * last_normal_.z;
        return h < info_.fingertip_radius_m;
    }

    std::string target_;
    double k_;
    std::optional<softfinger::Device> dev_;
    sf_info_t info_{};
    softfinger::LocalModel plane_;
    bool have_plane_ = false;
    cVector3d last_position_;
    bool have_position_ = false;
    cVector3d last_normal_{0.0, 0.0, 1.0};
};

static int failures = 0;
static void check(bool ok, const char *what) {
    if (!ok) {
        std::fprintf(stderr, "chai_device: FAILED: %s\n", what);
        failures++;
    }
}

int main(int argc, char **argv) {
    const std::string target = argc > 1 ? argv[1] : "tcp:127.0.0.1:7700";

    // Bad arguments are exceptions carrying the C code.
    try {
        softfinger::Device bad("serial:x");
        check(false, "a bad target opened");
    } catch (const softfinger::Error &e) {
        check(e.code() == SF_ERR_BAD_TARGET, "bad target code");
    }

    cSoftfingerDevice dev(target);
    if (!dev.open()) return 1;
    try {
        dev.device().set_stream(-5.0);
        check(false, "a negative rate was accepted");
    } catch (const softfinger::Error &e) {
        check(e.code() == SF_ERR_BAD_VALUE && !e.refused(), "negative rate code");
    }
    try {
        dev.device().arm();
        check(false, "armed before homing");
    } catch (const softfinger::Error &e) {
        check(e.refused() && e.code() == SF_ERR_REFUSED_WRONG_MODE, "arm before homing code");
    }
    if (!dev.calibrate()) return 1;

    // The application's world: a wall (normal +z) 2 mm into the fingertip where it is now.
    cVector3d p;
    while (!dev.getPosition(p)) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    const double r = dev.info().fingertip_radius_m, k = 200.0, c = 2.0;
    const double wall_z = p.z - r + 0.002;

    // A 1 kHz servo loop for 1.6 s of device time (a loaded host runs the virtual device slower
    // than real time): the arming ramp (0.5 s), then the 1 s that is checked.
    const uint64_t rate = dev.info().rate_hz;
    const uint64_t armed_tick = dev.device().latest()->tick;
    const uint64_t from = armed_tick + rate * 6 / 10, to = from + rate;
    auto next = std::chrono::steady_clock::now();
    uint32_t first_seq = 0;
    for (int i = 0; dev.device().latest()->tick < to; i++) {
        if (i > 20000) {
            std::fprintf(stderr, "chai_device: the device's clock does not advance\n");
            return 1;
        }
        dev.getPosition(p);
        double pen = r - (p.z - wall_z);
        if (!dev.setForce({0.0, 0.0, pen > 0.0 ? k * pen : 0.0})) return 1;
        if (i == 0) first_seq = dev.device().latest()->model_seq + 1;
        next += std::chrono::milliseconds(1);
        std::this_thread::sleep_until(next);
    }

    // The stream in order: the checked second against the wall's spring.
    std::vector<sf_state> states;
    while (auto s = dev.device().next(0.0)) states.push_back(*s);
    check(states.size() >= 1000, "fewer than 1000 samples streamed");
    int in_contact = 0;
    double worst = 0.0, worst_spring = 0.0;
    sf_state worst_sample{};
    for (const auto &s : states) {
        if (s.tick < from || s.tick >= to) continue;
        check(s.mode == SF_MODE_ARMED, "not armed while checked");
        if (static_cast<int32_t>(s.model_seq - first_seq) < 0 || s.contact == SF_CONTACT_BROKEN)
            continue;
        double f = k * (r - (s.position_m[2] - wall_z)) - c * s.velocity_m_s[2];
        if (f < 0.0) f = 0.0;
        double fmag = std::sqrt(s.force_n[0] * s.force_n[0] + s.force_n[1] * s.force_n[1] +
                                s.force_n[2] * s.force_n[2]);
        if (fmag >= dev.info().max_force_n * 0.999) continue; // the device's force cap
        if (std::fabs(s.force_n[2] - f) > worst) {
            worst = std::fabs(s.force_n[2] - f);
            worst_sample = s;
            worst_spring = f;
        }
        in_contact++;
    }
    const double bound_n = 5e-6; // derived in press.c
    std::printf("chai_device: %zu samples, %d in contact in the checked second, worst |f_n - spring| "
                "%.3g N (bound %.1g N)\n",
                states.size(), in_contact, worst, bound_n);
    check(in_contact >= 900, "fewer than 900 samples in contact");
    check(worst <= bound_n, "normal force off the wall's spring");
    if (worst > bound_n)
        std::fprintf(stderr,
                     "chai_device: worst sample: tick %llu (checked second from %llu), force %.6g N, "
                     "spring %.6g N, flags 0x%x, model seq %u (first %u), contact %d\n",
                     (unsigned long long)worst_sample.tick, (unsigned long long)from,
                     worst_sample.force_n[2], worst_spring, worst_sample.flags,
                     worst_sample.model_seq, first_seq, worst_sample.contact);
    dev.device().disarm();
    dev.close();
    if (failures) {
        std::fprintf(stderr, "chai_device: %d check(s) failed\n", failures);
        return 1;
    }
    std::printf("chai_device: ok\n");
    return 0;
}
