vsv-play-freevr.o: viewer/vsv-play-freevr.c format/vsv_cli.h \
 format/vsv_format.h viewer/vsv_overlay.h render/vsv_render.h \
 format/vsv_format.h viewer/vsv_player.h stream/vsv_clock.h \
 stream/vsv_pager.h viewer/freevr/freevr.h
format/vsv_cli.h:
format/vsv_format.h:
viewer/vsv_overlay.h:
render/vsv_render.h:
format/vsv_format.h:
viewer/vsv_player.h:
stream/vsv_clock.h:
stream/vsv_pager.h:
viewer/freevr/freevr.h:
