// The thesis format written back (issue 28, "keep what you set"): a scene file's text with
// its <Camera> and the <Settings> an interactive session changes replaced, everything else
// as it was (pugixml edits the parsed document; comments and order kept). Numbers are
// written with 9 significant digits, so that loading the result gives back the same floats.
#include <pugixml.hpp>

#include <cstdio>
#include <sstream>

#include "wavemmlt/error.h"
#include "wavemmlt/scene_desc.h"

namespace wmlt {

namespace {

std::string number(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.9g", v);
    return buf;
}

// parent's child element `name` (made when missing), its attributes set as given.
pugi::xml_node child(pugi::xml_node parent, const char* name) {
    pugi::xml_node c = parent.child(name);
    return c ? c : parent.append_child(name);
}
void setXyz(pugi::xml_node parent, const char* name, Vec3 v) {
    pugi::xml_node c = child(parent, name);
    for (const char* a : {"x", "y", "z"}) c.remove_attribute(a);
    c.append_attribute("x") = number(v.x).c_str();
    c.append_attribute("y") = number(v.y).c_str();
    c.append_attribute("z") = number(v.z).c_str();
}
void setValue(pugi::xml_node parent, const char* name, const std::string& value, const char* attribute = "value") {
    pugi::xml_node c = child(parent, name);
    c.remove_attribute(attribute);
    c.append_attribute(attribute) = value.c_str();
}

const char* tracerName(TracerKind t) {
    return t == TracerKind::MMLT ? "MMLT" : t == TracerKind::BPT ? "BPT" : t == TracerKind::LT ? "LT" : t == TracerKind::PSSMLT ? "PSSMLT" : "PT";
}

}  // namespace

std::string thesisSceneWithView(const std::string& xml, const std::string& name, const CameraDesc& cam, const Settings& st) {
    pugi::xml_document doc;
    const pugi::xml_parse_result parsed = doc.load_string(xml.c_str(), pugi::parse_default | pugi::parse_comments);
    pugi::xml_node scene = doc.child("Scene");
    if (!parsed || !scene) throw InputError(name, 0, "not a scene in the thesis format: cannot write its view back");
    pugi::xml_node c = child(scene, "Camera");
    setXyz(c, "Position", cam.position);
    setXyz(c, "LookAt", cam.lookAt);
    setXyz(c, "Up", cam.up);
    setValue(c, "FOV", number(cam.fovDegrees));
    setValue(c, "DOF", cam.dof ? "1" : "0");
    setValue(c, "F-Length", number(cam.focalLength));
    setValue(c, "F-Stop", number(cam.fStop));
    pugi::xml_node s = scene.child("Settings");
    if (!s) s = scene.prepend_child("Settings");
    setValue(s, "Width", std::to_string(st.width));
    setValue(s, "Height", std::to_string(st.height));
    setValue(s, "Sample", std::to_string(st.samples));
    setValue(s, "Tracer", tracerName(st.tracer), "name");
    setValue(s, "MaxPathLength", std::to_string(st.maxPathLength));
    setValue(s, "MinPathLength", std::to_string(st.minPathLength));
    setValue(s, "ProbLarge", number(st.probLarge));
    std::ostringstream out;
    doc.save(out, "  ");
    return out.str();
}

}  // namespace wmlt
