# Run at every build (target arcs_revision_stamp): writes OUT with the source
# tree's revision, "-dirty" when tracked files differ from it, only when that
# text changes. The programs read it at start (orchestration/version.cpp), so
# results rows name the code that was built, not the revision cmake saw when
# it configured -- and no program is relinked when the revision moves.
execute_process(COMMAND git rev-parse --short=12 HEAD WORKING_DIRECTORY ${SRC}
                OUTPUT_VARIABLE rev OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET RESULT_VARIABLE rc)
if(NOT rc EQUAL 0 OR NOT rev)
  set(rev "unknown")
else()
  execute_process(COMMAND git status --porcelain --untracked-files=no WORKING_DIRECTORY ${SRC}
                  OUTPUT_VARIABLE changes OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
  if(changes)
    set(rev "${rev}-dirty")
  endif()
endif()
set(old "")
if(EXISTS ${OUT})
  file(READ ${OUT} old)
endif()
if(NOT old STREQUAL "${rev}\n")
  file(WRITE ${OUT} "${rev}\n")
endif()
