# Writes OUT: a C++ file defining wmlt::kDefaultSceneXml with the text of IN.
file(READ ${IN} TEXT)
file(WRITE ${OUT} "// Generated from ${IN}: do not edit.\nnamespace wmlt {\nextern const char* const kDefaultSceneXml;\nconst char* const kDefaultSceneXml = R\"WMLTXML(${TEXT})WMLTXML\";\n}\n")
