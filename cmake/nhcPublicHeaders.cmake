# The public API is what is installed (docs/library.md, "The public API"): these entry points and
# the headers they include, found from their `#include "nhc/…"` lines. Everything else stays in
# the source tree. The list is read again when one of the headers changes (CMAKE_CONFIGURE_DEPENDS).
set(NHC_PUBLIC_ENTRY_POINTS
  nhc/codegen.hpp
  nhc/runtime/runtime.hpp
  nhc/base/number_text.hpp
  nhc/jit.hpp
  nhc/app/run_request.hpp
  nhc/linearize.hpp
  nhc/connect/shooting.hpp)
if(TARGET nhc_ensemble)
  list(APPEND NHC_PUBLIC_ENTRY_POINTS nhc/ensemble.hpp)
endif()
# The rooms whose headers may be public, each with its include root.
set(NHC_PUBLIC_ROOMS base codegen runtime jit app linearize connect ensemble)

# nhc_public_headers(OUT): "ROOM/nhc/…" of every entry point and every header it includes, sorted.
function(nhc_public_headers out)
  set(todo ${NHC_PUBLIC_ENTRY_POINTS})
  set(seen)
  set(found)
  while(todo)
    list(GET todo 0 header)
    list(REMOVE_AT todo 0)
    if(header IN_LIST seen)
      continue()
    endif()
    list(APPEND seen ${header})
    set(path "")
    foreach(room IN LISTS NHC_PUBLIC_ROOMS)
      if(EXISTS ${PROJECT_SOURCE_DIR}/${room}/${header})
        set(path ${room}/${header})
        break()
      endif()
    endforeach()
    if(NOT path)
      message(FATAL_ERROR "public header ${header}: not found in the rooms ${NHC_PUBLIC_ROOMS} "
                          "(a public header may include only public rooms' headers)")
    endif()
    list(APPEND found ${path})
    set_property(DIRECTORY ${PROJECT_SOURCE_DIR} APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/${path})
    file(STRINGS ${PROJECT_SOURCE_DIR}/${path} includes REGEX "^[ \t]*#[ \t]*include[ \t]+\"nhc/[^\"]+\"")
    foreach(line IN LISTS includes)
      string(REGEX REPLACE "^[ \t]*#[ \t]*include[ \t]+\"(nhc/[^\"]+)\".*" "\\1" included "${line}")
      list(APPEND todo ${included})
    endforeach()
  endwhile()
  list(SORT found)
  set(${out} ${found} PARENT_SCOPE)
endfunction()
