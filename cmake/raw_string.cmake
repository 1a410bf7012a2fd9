# bumprad_raw_string(VAR FILE): VAR becomes FILE's text as a C++ raw string literal, and CMake
# re-configures when FILE changes. Built-in scenes and web assets are compiled in with it.
function(bumprad_raw_string var file)
  set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${file})
  file(READ ${file} text)
  set(${var} "R\"bumprad_embed(${text})bumprad_embed\"" PARENT_SCOPE)
endfunction()
