// Native Embree 3 on a GLBENCH1 file (the mesh and rays `glint bench` traces): BVH
// build time, and closest/any-hit rays per second for single rays (rtcIntersect1 /
// rtcOccluded1) and packets of 4, 8 and 16 (rtcIntersect4/8/16, rtcOccluded4/8/16),
// timed as `glint bench` times them: each query run ROUNDS times, the median rate with
// the slowest and fastest; on one thread in CPU seconds of that thread, on several in
// wall-clock seconds. Camera rays go into packets as square-ish pixel tiles (2x2, 4x2,
// 4x4), random rays in the order they come. Prints one JSON object whose keys match
// `glint bench --json`'s; every closest hit is checked against the file's reference.
//
// Build: g++ -O2 -std=c++17 embree_native.cpp -lembree3 -lpthread -o embree_native
// Usage: [EMBREE_ROBUST=1] [EMBREE_ISA=avx2] embree_native FILE THREADS ROUNDS
#include <embree3/rtcore.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <fstream>
#include <functional>
#include <limits>
#include <string>
#include <thread>
#include <vector>

struct Ray6 {
    float o[3], d[3];
};

struct Input {
    std::vector<float> positions;
    std::vector<uint32_t> indices;
    std::vector<Ray6> rays[2];  // coherent, incoherent
    std::vector<float> reference[2];
};

static bool read_input(const char* path, Input& in) {
    std::ifstream f(path, std::ios::binary);
    char magic[8];
    if (!f.read(magic, 8) || std::memcmp(magic, "GLBENCH1", 8) != 0) return false;
    uint32_t counts[4];
    if (!f.read(reinterpret_cast<char*>(counts), sizeof counts)) return false;
    in.positions.resize(3 * size_t(counts[0]));
    in.indices.resize(3 * size_t(counts[1]));
    in.rays[0].resize(counts[2]);
    in.rays[1].resize(counts[3]);
    in.reference[0].resize(counts[2]);
    in.reference[1].resize(counts[3]);
    auto read = [&](void* p, size_t bytes) { return bool(f.read(static_cast<char*>(p), std::streamsize(bytes))); };
    return read(in.positions.data(), in.positions.size() * 4) && read(in.indices.data(), in.indices.size() * 4) &&
           read(in.rays[0].data(), in.rays[0].size() * 24) && read(in.rays[1].data(), in.rays[1].size() * 24) &&
           read(in.reference[0].data(), in.reference[0].size() * 4) &&
           read(in.reference[1].data(), in.reference[1].size() * 4);
}

static double clock_seconds(clockid_t id) {
    timespec t;
    clock_gettime(id, &t);
    return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

static RTCScene build(RTCDevice device, const Input& in) {
    RTCScene scene = rtcNewScene(device);
    rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_MEDIUM);
    // EMBREE_ROBUST=1: Embree's robust mode (robust traversal and a Pluecker triangle
    // test meant to be watertight, as glint's test is; the default, Moeller-Trumbore,
    // can miss along shared edges).
    const char* robust = std::getenv("EMBREE_ROBUST");
    if (robust && std::strcmp(robust, "1") == 0) rtcSetSceneFlags(scene, RTC_SCENE_FLAG_ROBUST);
    RTCGeometry geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                           3 * sizeof(float), in.positions.size() / 3));
    std::copy(in.positions.begin(), in.positions.end(), vb);
    auto* ib = static_cast<uint32_t*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                              3 * sizeof(uint32_t), in.indices.size() / 3));
    std::copy(in.indices.begin(), in.indices.end(), ib);
    rtcCommitGeometry(geom);
    rtcAttachGeometry(scene, geom);
    rtcReleaseGeometry(geom);
    rtcCommitScene(scene);
    return scene;
}

// The order in which camera rays of a square image go into packets of `width`: tiles
// of 2x2 (4), 4x2 (8) or 4x4 (16) pixels; row order when the image is not square.
static std::vector<size_t> tile_order(size_t n, int width) {
    std::vector<size_t> order(n);
    size_t side = size_t(std::llround(std::sqrt(double(n))));
    int tw = width == 4 ? 2 : 4, th = width / tw;
    if (side * side != n || side % 4 != 0) {
        for (size_t i = 0; i < n; i++) order[i] = i;
        return order;
    }
    size_t k = 0;
    for (size_t ty = 0; ty < side / th; ty++)
        for (size_t tx = 0; tx < side / tw; tx++)
            for (int j = 0; j < width; j++) order[k++] = (th * ty + j / tw) * side + tw * tx + j % tw;
    return order;
}

// Runs `work(begin, end)` over [0, n) in chunks of 1024 on `threads` threads.
static void parallel(size_t n, int threads, const std::function<void(size_t, size_t)>& work) {
    std::atomic<size_t> next{0};
    auto worker = [&] {
        for (;;) {
            size_t begin = next.fetch_add(1024);
            if (begin >= n) return;
            work(begin, std::min(n, begin + 1024));
        }
    };
    if (threads == 1) return worker();
    std::vector<std::thread> pool;
    for (int t = 0; t < threads; t++) pool.emplace_back(worker);
    for (auto& t : pool) t.join();
}

struct Rate {
    double median, min, max;
};

static Rate time_rounds(size_t rays, int threads, int rounds, const std::function<void()>& run) {
    std::vector<double> rates;
    for (int r = 0; r < rounds; r++) {
        auto wall = std::chrono::steady_clock::now();
        double cpu = clock_seconds(CLOCK_THREAD_CPUTIME_ID);
        run();
        double seconds = threads == 1 ? clock_seconds(CLOCK_THREAD_CPUTIME_ID) - cpu
                                       : std::chrono::duration<double>(std::chrono::steady_clock::now() - wall).count();
        rates.push_back(double(rays) / seconds);
    }
    std::sort(rates.begin(), rates.end());
    return {rates[rates.size() / 2], rates.front(), rates.back()};
}

static std::string json;
static void put(const std::string& key, double value) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.9g", value);
    json += (json.empty() ? "{" : ", ") + ("\"" + key + "\": ") + buf;
}
static void put_rate(const std::string& key, Rate r) {
    put(key + "_rays_per_s", r.median);
    put(key + "_rays_per_s_min", r.min);
    put(key + "_rays_per_s_max", r.max);
}

static void init_ray(RTCRay& r, const Ray6& s) {
    r.org_x = s.o[0], r.org_y = s.o[1], r.org_z = s.o[2];
    r.dir_x = s.d[0], r.dir_y = s.d[1], r.dir_z = s.d[2];
    r.tnear = 0.0f, r.tfar = std::numeric_limits<float>::infinity();
    r.time = 0.0f, r.mask = ~0u, r.id = 0, r.flags = 0;
}

// Packets of N rays in SOA layout: Embree's RTCRayHitN/RTCRayN for N = 4, 8, 16.
template <int N, class RayHit, class Ray>
static void packets(RTCScene scene, const std::vector<Ray6>& rays, const std::vector<size_t>& order, int threads,
                    int rounds, const std::string& key, std::vector<float>& t_out, std::vector<char>& blocked_out,
                    void (*intersect)(const int*, RTCScene, RTCIntersectContext*, RayHit*),
                    void (*occluded)(const int*, RTCScene, RTCIntersectContext*, Ray*)) {
    auto fill = [&](auto& ray, size_t base, int* valid) {
        for (int k = 0; k < N; k++) {
            size_t i = base + k;
            valid[k] = i < order.size() ? -1 : 0;
            const Ray6& s = rays[order[std::min(i, order.size() - 1)]];
            ray.org_x[k] = s.o[0], ray.org_y[k] = s.o[1], ray.org_z[k] = s.o[2];
            ray.dir_x[k] = s.d[0], ray.dir_y[k] = s.d[1], ray.dir_z[k] = s.d[2];
            ray.tnear[k] = 0.0f, ray.tfar[k] = std::numeric_limits<float>::infinity();
            ray.time[k] = 0.0f, ray.mask[k] = ~0u, ray.id[k] = 0, ray.flags[k] = 0;
        }
    };
    Rate closest = time_rounds(rays.size(), threads, rounds, [&] {
        parallel(rays.size(), threads, [&](size_t begin, size_t end) {
            RTCIntersectContext ctx;
            rtcInitIntersectContext(&ctx);
            alignas(64) RayHit rh;
            alignas(64) int valid[N];
            for (size_t base = begin; base < end; base += N) {
                fill(rh.ray, base, valid);
                for (int k = 0; k < N; k++) rh.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
                intersect(valid, scene, &ctx, &rh);
                for (int k = 0; k < N && base + k < order.size(); k++)
                    t_out[order[base + k]] = rh.hit.geomID[k] == RTC_INVALID_GEOMETRY_ID
                                                 ? std::numeric_limits<float>::infinity()
                                                 : rh.ray.tfar[k];
            }
        });
    });
    Rate any = time_rounds(rays.size(), threads, rounds, [&] {
        parallel(rays.size(), threads, [&](size_t begin, size_t end) {
            RTCIntersectContext ctx;
            rtcInitIntersectContext(&ctx);
            alignas(64) Ray ray;
            alignas(64) int valid[N];
            for (size_t base = begin; base < end; base += N) {
                fill(ray, base, valid);
                occluded(valid, scene, &ctx, &ray);
                for (int k = 0; k < N && base + k < order.size(); k++)
                    blocked_out[order[base + k]] = ray.tfar[k] < 0.0f;
            }
        });
    });
    put_rate(key + "_closest_packet" + std::to_string(N), closest);
    put_rate(key + "_any_packet" + std::to_string(N), any);
}

int main(int argc, char** argv) {
    if (argc != 4) {
        std::fprintf(stderr, "usage: %s GLBENCH1-FILE THREADS ROUNDS\n", argv[0]);
        return 2;
    }
    Input in;
    if (!read_input(argv[1], in)) {
        std::fprintf(stderr, "%s: not a readable GLBENCH1 file\n", argv[1]);
        return 1;
    }
    int threads = std::max(1, std::atoi(argv[2])), rounds = std::max(1, std::atoi(argv[3]));
    std::string config = "threads=" + std::to_string(threads);
    // EMBREE_ISA=avx2 (or sse4.2, avx512): the kernels Embree may pick; by default the
    // best the CPU has (AVX-512 on some of these VMs, where glint uses AVX2).
    if (const char* isa = std::getenv("EMBREE_ISA"); isa && *isa) config += std::string(",isa=") + isa;
    RTCDevice device = rtcNewDevice(config.c_str());
    // Build: best of 3, wall and process CPU seconds, on the device's threads.
    double build_wall = 1e30, build_cpu = 1e30;
    RTCScene scene = nullptr;
    for (int r = 0; r < 3; r++) {
        if (scene) rtcReleaseScene(scene);
        auto wall = std::chrono::steady_clock::now();
        double cpu = clock_seconds(CLOCK_PROCESS_CPUTIME_ID);
        scene = build(device, in);
        build_cpu = std::min(build_cpu, clock_seconds(CLOCK_PROCESS_CPUTIME_ID) - cpu);
        build_wall = std::min(build_wall, std::chrono::duration<double>(std::chrono::steady_clock::now() - wall).count());
    }
    put("triangles", double(in.indices.size() / 3));
    put("build_s", build_cpu);
    put("build_wall_s", build_wall);
    put("trace_threads", threads);
    const char* names[2] = {"coherent", "incoherent"};
    for (int kind = 0; kind < 2; kind++) {
        const auto& rays = in.rays[kind];
        std::string key = names[kind];
        std::vector<float> t(rays.size());
        std::vector<char> blocked(rays.size());
        Rate closest = time_rounds(rays.size(), threads, rounds, [&] {
            parallel(rays.size(), threads, [&](size_t begin, size_t end) {
                RTCIntersectContext ctx;
                rtcInitIntersectContext(&ctx);
                for (size_t i = begin; i < end; i++) {
                    RTCRayHit rh;
                    init_ray(rh.ray, rays[i]);
                    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
                    rtcIntersect1(scene, &ctx, &rh);
                    t[i] = rh.hit.geomID == RTC_INVALID_GEOMETRY_ID ? std::numeric_limits<float>::infinity()
                                                                    : rh.ray.tfar;
                }
            });
        });
        Rate any = time_rounds(rays.size(), threads, rounds, [&] {
            parallel(rays.size(), threads, [&](size_t begin, size_t end) {
                RTCIntersectContext ctx;
                rtcInitIntersectContext(&ctx);
                for (size_t i = begin; i < end; i++) {
                    RTCRay r;
                    init_ray(r, rays[i]);
                    rtcOccluded1(scene, &ctx, &r);
                    blocked[i] = r.tfar < 0.0f;
                }
            });
        });
        put_rate(key + "_closest", closest);
        put_rate(key + "_any", any);
        size_t disagree = 0, hits = 0;
        for (size_t i = 0; i < rays.size(); i++) {
            float a = t[i], b = in.reference[kind][i];
            bool differ = std::isfinite(a) != std::isfinite(b) ||
                          (std::isfinite(a) && std::fabs(a - b) > 1e-4f * std::max(b, 1.0f));
            disagree += differ;
            hits += std::isfinite(a);
            if (bool(blocked[i]) != std::isfinite(a)) disagree++;
        }
        put(key + "_hit_fraction", double(hits) / double(std::max<size_t>(rays.size(), 1)));
        put(key + "_disagree_with_reference", double(disagree));
        std::vector<float> tp(rays.size());
        std::vector<char> bp(rays.size());
        auto check = [&](int width) {
            size_t bad = 0;
            for (size_t i = 0; i < rays.size(); i++)
                bad += (std::isfinite(tp[i]) != std::isfinite(t[i])) || bool(bp[i]) != bool(blocked[i]);
            put(key + "_packet" + std::to_string(width) + "_disagree_with_single", double(bad));
        };
        auto order_for = [&](int width) {
            if (kind == 0) return tile_order(rays.size(), width);
            std::vector<size_t> order(rays.size());
            for (size_t i = 0; i < order.size(); i++) order[i] = i;
            return order;
        };
        packets<4, RTCRayHit4, RTCRay4>(scene, rays, order_for(4), threads, rounds, key, tp, bp, rtcIntersect4,
                                        rtcOccluded4);
        check(4);
        packets<8, RTCRayHit8, RTCRay8>(scene, rays, order_for(8), threads, rounds, key, tp, bp, rtcIntersect8,
                                        rtcOccluded8);
        check(8);
        packets<16, RTCRayHit16, RTCRay16>(scene, rays, order_for(16), threads, rounds, key, tp, bp, rtcIntersect16,
                                           rtcOccluded16);
        check(16);
    }
    rtcReleaseScene(scene);
    rtcReleaseDevice(device);
    std::printf("%s}\n", json.c_str());
    return 0;
}
