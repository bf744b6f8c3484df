// A bound on how deeply a scene file's elements nest, checked on the parsed document
// before any recursive walk of it (the importers' own, and their messages' element paths),
// so that a hostile file is refused with a message instead of exhausting the stack.
// pugixml parses and frees a document without recursion, so the bound is needed only
// here (docs/reliability.md).
#pragma once
#include <pugixml.hpp>

namespace wmlt {

// Elements nested deeper than this are refused: the root element is at depth 1. Real
// scenes nest a few levels (Mitsuba's twosided, mask and bumpmap wrappers, a texture
// inside; the thesis format at most 4), so 100 is far above any of them.
constexpr int kMaxXmlNesting = 100;

// The first element in document order that lies deeper than `limit` below `doc`, or a
// null node; an iterative walk (first child, next sibling, back up through parents).
inline pugi::xml_node firstNestedDeeperThan(pugi::xml_node doc, int limit = kMaxXmlNesting) {
    int depth = 0;
    pugi::xml_node n = doc.first_child();
    if (n) depth = 1;
    while (n) {
        if (n.type() == pugi::node_element && depth > limit) return n;
        if (pugi::xml_node c = n.first_child()) {
            n = c;
            ++depth;
            continue;
        }
        while (n && !n.next_sibling() && n != doc) {
            n = n.parent();
            --depth;
        }
        if (!n || n == doc) break;
        n = n.next_sibling();
    }
    return pugi::xml_node();
}

}  // namespace wmlt
