// The Mitsuba importer's state (load_mitsuba.cpp: the scene, shapes, emitters, sensor and
// integrator; mitsuba_materials.cpp: the BSDFs).
#pragma once
#include <filesystem>
#include <functional>
#include <set>

#include "scene/mitsuba/mitsuba_xml.h"

namespace wmlt::mitsuba {

class Importer {
public:
    Importer(const std::string& base, const Defines& defines, const LoadOptions& options = {}) : base_(base), options_(options) {
        for (const auto& d : defines) params_[d.first] = d.second;
        for (const auto& d : defines) overridden_.insert(d.first);
    }
    SceneDesc run(const std::string& xml, const std::string& name);

private:
    Files files_;
    std::string base_;
    LoadOptions options_;
    std::map<std::string, std::string> params_;
    std::set<std::string> overridden_;
    std::map<std::string, Node> ids_;
    std::map<const void*, int> materialOf_;  // bsdf element -> material index
    std::map<const void*, int> textureOf_;   // texture element -> texture index
    std::map<const void*, int> groupOf_;     // shapegroup element -> group index
    std::map<const void*, int> mediumOf_;    // medium element -> SceneDesc::media index
    int currentGroup_ = -1;                  // the shapegroup whose shapes are being read
    bool camel_ = false;
    SceneDesc s_;
    bool haveSensor_ = false, haveIntegrator_ = false;
    static constexpr int kDiskSegments = 512;

    Props props(Node n) {
        Props p(files_, n, camel_);
        p.setIds(&ids_);
        p.setContext(&base_, &s_.warnings, &s_);
        return p;
    }
    std::string resolve(const std::string& f) const {
        std::filesystem::path p(f);
        if (p.is_relative() && !base_.empty()) p = std::filesystem::path(base_) / p;
        return p.lexically_normal().string();
    }
    void warn(Node n, const std::string& msg) { s_.warnings.push_back(files_.where(n) + ": " + msg); }
    void collect(Node scene, int depth);
    void topLevel(Node scene);
    float ior(Props& p, const char* name, float def);
    int material(Node bsdf);
    int texture(Node tex);
    Node textureParam(Props& p, const std::string& name);
    void materialParams(Props& p, MaterialDesc& m);
    void principledParams(Props& p, MaterialDesc& m);
    void shape(Node n);
    int shapeGroup(Node n);
    void instance(Node n);
    void emitter(Node n, int shape);
    void sensor(Node n);
    FilterDesc reconstructionFilter(Node rf);
    void integrator(Node n);
    // mitsuba_media.cpp
    int medium(Node n);
    void shapeMedia(Props& p, ShapeDesc& sh);
};

}  // namespace wmlt::mitsuba
