# Writes OUT: a C++ file defining the CIE 1931 2-degree colour matching functions and the
# CIE D65 illuminant, read from Debian's colord-data (CMF: 360-830 nm, D65: 300-830 nm,
# both every 5 nm; CGATS text: one data set per line between BEGIN_DATA and END_DATA).
function(cgats_rows FILE VAR)
  if(NOT EXISTS ${FILE})
    message(FATAL_ERROR "${FILE} is missing: install Debian's colord-data (scripts/setup.sh does)")
  endif()
  file(STRINGS ${FILE} LINES)
  set(IN_DATA OFF)
  set(ROWS "")
  foreach(L IN LISTS LINES)
    string(STRIP "${L}" L)
    if(L STREQUAL "END_DATA")
      set(IN_DATA OFF)
    elseif(IN_DATA)
      string(REGEX REPLACE "[ \t]+" ", " L "${L}")
      string(APPEND ROWS "    {${L}},\n")
    elseif(L STREQUAL "BEGIN_DATA")
      set(IN_DATA ON)
    endif()
  endforeach()
  set(${VAR} "${ROWS}" PARENT_SCOPE)
endfunction()
cgats_rows(${CMF} XYZ_ROWS)
cgats_rows(${D65} D65_ROWS)
file(WRITE ${OUT} "// Generated from ${CMF} and ${D65} (Debian's colord-data): do not edit.
namespace wmlt::cie {
extern const double kXyz[3][95];  // x-bar, y-bar, z-bar at 360, 365, ..., 830 nm
const double kXyz[3][95] = {
${XYZ_ROWS}};
extern const double kD65[1][107];  // D65 at 300, 305, ..., 830 nm
const double kD65[1][107] = {
${D65_ROWS}};
}
")
